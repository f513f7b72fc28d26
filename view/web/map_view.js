// The 2D map: its frame drawn from the model, and pan and zoom.
"use strict";
function drawFrame(now) {
  const W = overlay.clientWidth, H = overlay.clientHeight;
  if (overlay.width !== W || overlay.height !== H) { overlay.width = W; overlay.height = H; }
  const t = transform();
  ctx.clearRect(0, 0, W, H);
  const drawn = drawVehicles(t, () => {
    if (featuresOnCanvas()) drawFeatureCache(now, t);
    drawSelected(t);
  });
  drawn.features = state.features.size;
  drawn.featureMode = featuresOnCanvas() ? featureCache.mode : "svg";
  window.dtView.drawn = drawn;
  $("vehiclemode").textContent = drawn.mode === "cells"
    ? `${drawn.vehicles} in view, per ${CELL_PX}-pixel cell (zoom in for markers)`
    : `${drawn.vehicles} in view`;
}

// ---- pan and zoom: the SVG viewBox in metres ----
function applyView() {
  const v = state.view;
  $("map").setAttribute("viewBox", `${v.x} ${v.y} ${v.w} ${v.h}`);
  frame.dirty = true;
  frame.viewChangedAt = performance.now();
  if (typeof updateRelief === "function") updateRelief();  // relief_tiles.js, loaded next
}
window.addEventListener("resize", () => { frame.dirty = true; });
function toMap(ev) {
  const r = $("map").getBoundingClientRect(), v = state.view;
  const scale = Math.max(v.w / r.width, v.h / r.height);
  const ox = v.x + (v.w - r.width * scale) / 2, oy = v.y + (v.h - r.height * scale) / 2;
  return [ox + (ev.clientX - r.left) * scale, oy + (ev.clientY - r.top) * scale, scale];
}
let drag = null;
$("map").addEventListener("mousedown", (ev) => { drag = { x: ev.clientX, y: ev.clientY, moved: false }; });
window.addEventListener("mouseup", () => { setTimeout(() => { drag = null; }, 0); });
window.addEventListener("mousemove", (ev) => {
  if (!drag) return;
  const [, , scale] = toMap(ev);
  const dx = ev.clientX - drag.x, dy = ev.clientY - drag.y;
  if (Math.abs(dx) + Math.abs(dy) > 2) drag.moved = true;
  state.view.x -= dx * scale;
  state.view.y -= dy * scale;
  drag.x = ev.clientX;
  drag.y = ev.clientY;
  applyView();
});
$("map").addEventListener("wheel", (ev) => {
  ev.preventDefault();
  const [mx, my] = toMap(ev);
  const k = ev.deltaY > 0 ? 1.2 : 1 / 1.2, v = state.view;
  v.x = mx - (mx - v.x) * k; v.y = my - (my - v.y) * k; v.w *= k; v.h *= k;
  applyView();
}, { passive: false });
