// Features as SVG elements while they are few (each clickable, styled by the stylesheet).
"use strict";
function el(tag, attrs, parent) {
  const e = document.createElementNS(SVG, tag);
  for (const [k, v] of Object.entries(attrs)) e.setAttribute(k, v);
  if (parent) parent.appendChild(e);
  return e;
}
function along(f, d) {  // the point d metres from (x, z) along the feature's direction
  return [f.x + d * Math.cos(f.dir), f.z + d * Math.sin(f.dir)];
}
function strip(f, from, to, width) {  // a rectangle from..to along the direction, as points
  const nx = -Math.sin(f.dir) * width / 2, nz = Math.cos(f.dir) * width / 2;
  const [ax, az] = along(f, from), [bx, bz] = along(f, to);
  return [[ax + nx, az + nz], [bx + nx, bz + nz], [bx - nx, bz - nz], [ax - nx, az - nz]]
    .map(([x, z]) => `${x},${Y(z)}`).join(" ");
}

function drawFeature(f) {
  if (!(f.id in window.dtView.drawnAt)) window.dtView.drawnAt[f.id] = Date.now();
  if (featuresOnCanvas()) { if (state.selected === f.id) showFeature(); return; }
  const layer = $("features");
  let g = layer.querySelector(`[data-id="${f.id}"]`);
  if (g) g.remove();
  g = el("g", { class: "feature", "data-id": f.id, "data-type": f.type }, layer);
  const placed = f.placed ? "" : "4 3";
  if (f.type === "crater") {
    el("circle", { cx: f.x, cy: Y(f.z), r: f.radius, fill: "rgba(90,60,30,0.35)",
                   stroke: "#ffb060", "stroke-width": 1.5, "stroke-dasharray": placed }, g);
  } else if (f.type === "berm") {
    const piece = (f.history || []).some((e) => e.kind === "breach" && e.feature === f.id);
    el("polygon", { points: strip(f, 0, f.length, f.width), fill: "rgba(200,170,90,0.4)",
                    stroke: piece ? "#ff60d0" : "#e8d080", "stroke-width": 1.5,
                    "stroke-dasharray": placed }, g);
  } else if (f.type === "bridge") {
    // The solids vehicles meet (the server's plan of vehicle/bridge_solids.h): deck slabs, the
    // span filled; piers; a destroyed span's rubble.
    const destroyed = f.status === "destroyed";
    const colour = destroyed ? "#ff3b2b" : "#80d0ff";
    const pts = (s) => s.corners.map(([x, z]) => `${x},${Y(z)}`).join(" ");
    (f.solids || []).forEach((s, i) => {
      const span = s.kind === "deck" && !destroyed && i === 1;
      if (s.kind === "deck") {
        el("polygon", { points: pts(s), "data-solid": "deck",
                        fill: span ? "rgba(120,200,255,0.45)" : "none", stroke: colour,
                        "stroke-width": span ? 2 : 1,
                        "stroke-dasharray": span ? placed : "3 2" }, g);
      } else if (s.kind === "rubble") {
        el("polygon", { points: pts(s), "data-solid": "rubble", fill: "rgba(255,60,40,0.25)",
                        stroke: colour, "stroke-width": 2, "stroke-dasharray": "6 3" }, g);
      } else {
        el("polygon", { points: pts(s), "data-solid": "pier", fill: colour, stroke: "none" }, g);
      }
    });
  } else if (f.type === "ditch" || f.type === "berm_line") {
    // The centre line, as wide as each segment's mean top width.
    const piece = (f.history || []).some((e) => e.kind === "breach" && e.feature === f.id);
    const cut = f.type === "ditch";
    for (let i = 0; i + 1 < f.points.length; ++i) {
      const [ax, az, , aw] = f.points[i], [bx, bz, , bw] = f.points[i + 1];
      el("line", { x1: ax, y1: Y(az), x2: bx, y2: Y(bz), "stroke-linecap": "round",
                   stroke: cut ? "rgba(70,40,20,0.55)" : "rgba(200,170,90,0.45)",
                   "stroke-width": (aw + bw) / 2 }, g);
    }
    el("polyline", { points: f.points.map(([x, z]) => `${x},${Y(z)}`).join(" "), fill: "none",
                     stroke: piece ? "#ff60d0" : cut ? "#c08050" : "#e8d080", "stroke-width": 1.5,
                     "stroke-dasharray": placed }, g);
  } else if (f.type === "area") {
    const fills = { water: "rgba(40,110,220,0.45)", mud: "rgba(110,80,40,0.45)",
                    burnt: "rgba(30,30,30,0.45)", oil: "rgba(20,10,30,0.55)" };
    el("polygon", { points: f.points.map(([x, z]) => `${x},${Y(z)}`).join(" "),
                    fill: fills[f.soil] || "rgba(160,160,160,0.35)", stroke: "#a0c0ff",
                    "stroke-width": 1, "stroke-dasharray": placed }, g);
  }
  g.addEventListener("click", (ev) => { ev.stopPropagation(); select(f.id); });
  if (state.selected === f.id) { g.classList.add("selected"); showFeature(); }
}
function removeFeature(id) {
  const g = $("features").querySelector(`[data-id="${id}"]`);
  if (g) g.remove();
  state.features.delete(id);
  ++frame.featuresVersion; frame.dirty = true;
  if (state.selected === id) { state.selected = null; showFeature(); }
}
