// The live view's page: one WebSocket, a snapshot then deltas (docs/view.md "Messages").
"use strict";
const SVG = "http://www.w3.org/2000/svg";
const state = {
  size_x: 1000, size_z: 1000, exercise: null, seq: 0, features: new Map(), processes: [],
  vehicles: new VehicleTable(),
  selected: null, view: null, ws: null, req: 0,
};
// For tests and for the curious: when each feature was first drawn (Date.now()), and the
// sequence of the last message applied.
window.dtView = { state, drawnAt: {}, appliedSeq: 0, snapshotAt: 0, deltas: 0, frames: 0,
                  lagMs: 0, maxLagMs: 0, drawn: null, terrainVersion: 0, wsBytes: 0,
                  // The page's own time: applying messages (parse included) and drawing.
                  cost: { messages: 0, applyMs: 0, draws: 0, drawMs: 0 }, ownerRgb: (n) => ownerRgb(n), vehicleOf };

const $ = (id) => document.getElementById(id);
function hue(text) {
  let h = 0;
  for (const c of text) h = (h * 31 + c.charCodeAt(0)) >>> 0;
  // Names that differ in their last letter only (node-1, node-2) would be 1 degree apart: spread
  // consecutive hashes by the golden angle.
  return Math.round((h % 360) * 137.508) % 360;
}
const ownerColour = (name) => `hsl(${hue(name)}, 80%, 60%)`;
const digestColour = (d) => (d ? `hsl(${hue(d)}, 70%, 55%)` : "#555");
// SVG y grows down; the terrain's z grows north.
const Y = (z) => state.size_z - z;

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

// ---- vehicles (and features when there are many) on a canvas over the map ----
// One SVG element per vehicle stalls the page at thousands; the canvas is redrawn at most once
// per animation frame, from the page's model (docs/view.md "Drawing at scale").
// Vehicles are kept in a VehicleTable (vehicle_table.js); a row, as tests read one, is
// [id, owner, type, x, z, heading, speed, alive, slot].
function vehicleOf([id, owner, type, x, z, heading, speed, alive]) {
  return { id, owner, type, x, z, heading, speed, alive };
}
const MARKER_PX = 7;          // a marker's half length on the screen, whatever the zoom
const CELL_PX = 14;           // an aggregate cell's side
const GLYPH_MAX_PX = 6;       // the largest cell's glyph: (6 / 14)² of the ground at most
const MARKERS_MAX = 3000;     // more visible than this: per-cell counts
const MARKER_COVER_MAX = 0.12;  // nor when markers would cover more of the map than this
const FEATURE_SVG_MAX = 2000;   // more features than this: drawn on the canvas too
const FEATURE_SHAPES_MAX = 6000;  // more in view than this: a density picture
function hslRgb(h, s, l) {  // CSS hsl() as [r, g, b], so pixels can be matched exactly
  const a = s * Math.min(l, 1 - l);
  const f = (n) => { const k = (n + h / 30) % 12;
    return Math.round(255 * (l - a * Math.max(-1, Math.min(k - 3, 9 - k, 1)))); };
  return [f(0), f(8), f(4)];
}
const rgbCache = new Map();
function ownerRgb(name) {
  let c = rgbCache.get(name);
  if (!c) { c = hslRgb(hue(name), 0.8, 0.6); rgbCache.set(name, c); }
  return c;
}
const css = ([r, g, b]) => `rgb(${r},${g},${b})`;
const overlay = $("overlay");
const ctx = overlay.getContext("2d");
const frame = { dirty: true, viewChangedAt: 0, featuresVersion: 0 };
const featureCache = { canvas: document.createElement("canvas"), version: -1, t: null,
                       renderedAt: 0 };

// The map's transform, as the SVG's viewBox (xMidYMid meet) has it: metres per pixel and the
// map point at the canvas's top left.
function transform() {
  const W = overlay.clientWidth, H = overlay.clientHeight, v = state.view;
  const s = Math.max(v.w / W, v.h / H);
  return { W, H, s, ox: v.x + (v.w - W * s) / 2, oy: v.y + (v.h - H * s) / 2 };
}
function featuresOnCanvas() { return state.features.size > FEATURE_SVG_MAX; }
function setVehicle(row) { state.vehicles.setRow(row); frame.dirty = true; }
function removeVehicle(id) { state.vehicles.delete(id); frame.dirty = true; }

// Features as a few batched paths, culled to the rectangle [x0, x1] x [y0, y1] (map y).
function paintFeatures(c, t, x0, y0, x1, y1) {
  const px = (x) => (x - t.ox) / t.s, py = (y) => (y - t.oy) / t.s;
  const craters = new Path2D(), dashed = new Path2D(), strips = new Path2D(),
        bridges = new Path2D(), broken = new Path2D(), others = new Path2D();
  const poly = (path, pts) => {
    pts.forEach(([x, z], i) => (i ? path.lineTo(px(x), py(Y(z))) : path.moveTo(px(x), py(Y(z)))));
    path.closePath();
  };
  const stripPts = (f, from, to, width) => {
    const nx = -Math.sin(f.dir) * width / 2, nz = Math.cos(f.dir) * width / 2;
    const [ax, az] = along(f, from), [bx, bz] = along(f, to);
    return [[ax + nx, az + nz], [bx + nx, bz + nz], [bx - nx, bz - nz], [ax - nx, az - nz]];
  };
  const inView = [];
  for (const f of state.features.values()) {
    const reach = f.radius || f.length || f.span || 50;
    const y = Y(f.z);
    if (f.x + reach < x0 || f.x - reach > x1 || y + reach < y0 || y - reach > y1) continue;
    inView.push(f);
  }
  // Too many outlines to draw, or to read: a density picture of all but the bridges.
  featureCache.mode = inView.length > FEATURE_SHAPES_MAX ? "density" : "shapes";
  if (featureCache.mode === "density") paintDensity(c, t, inView);
  for (const f of inView) {
    const y = Y(f.z);
    if (featureCache.mode === "density" && f.type !== "bridge") continue;
    if (f.type === "crater") {
      const r = Math.max(f.radius / t.s, 1.5), path = f.placed ? craters : dashed;
      path.moveTo(px(f.x) + r, py(y));
      path.arc(px(f.x), py(y), r, 0, 2 * Math.PI);
    } else if (f.type === "berm") {
      poly(f.placed ? strips : dashed, stripPts(f, 0, f.length, Math.max(f.width, 2 * t.s)));
    } else if (f.type === "bridge") {
      poly(f.status === "destroyed" ? broken : bridges, stripPts(f, 0, f.span, f.width));
    } else if (f.points) {
      const pts = f.points.map(([x, z]) => [x, z]);
      if (f.type === "area") poly(others, pts);
      else pts.forEach(([x, z], i) => (i ? others.lineTo(px(x), py(Y(z)))
                                         : others.moveTo(px(x), py(Y(z)))));
    }
  }
  c.lineWidth = 1;
  c.fillStyle = "rgba(90,60,30,0.35)"; c.strokeStyle = "#ffb060";
  c.fill(craters); c.stroke(craters);
  c.fillStyle = "rgba(200,170,90,0.4)"; c.strokeStyle = "#e8d080";
  c.fill(strips); c.stroke(strips);
  c.fillStyle = "rgba(120,200,255,0.45)"; c.strokeStyle = "#80d0ff";
  c.fill(bridges); c.stroke(bridges);
  c.fillStyle = "rgba(255,60,40,0.25)"; c.strokeStyle = "#ff3b2b";
  c.fill(broken); c.stroke(broken);
  c.strokeStyle = "#a0c0ff"; c.stroke(others);
  c.setLineDash([4, 3]); c.strokeStyle = "#ffb060"; c.stroke(dashed); c.setLineDash([]);
}

// Features as 3-pixel bins, each in the colour of the kind with most features there (craters
// orange, berms sand, the rest blue-grey), more opaque the more it holds.
function paintDensity(c, t, list) {
  const B = 3, w = Math.ceil(c.canvas.width / B), h = Math.ceil(c.canvas.height / B);
  const kinds = new Uint16Array(w * h * 3);
  for (const f of list) {
    const i = Math.floor((f.x - t.ox) / t.s / B), j = Math.floor((Y(f.z) - t.oy) / t.s / B);
    if (i < 0 || j < 0 || i >= w || j >= h) continue;
    const k = f.type === "crater" ? 0 : f.type === "berm" || f.type === "berm_line" ? 1 : 2;
    ++kinds[(j * w + i) * 3 + k];
  }
  const colours = [[255, 176, 96], [232, 208, 128], [160, 192, 255]];
  const img = new ImageData(w, h);
  for (let b = 0; b < w * h; ++b) {
    const n = kinds[b * 3] + kinds[b * 3 + 1] + kinds[b * 3 + 2];
    if (!n) continue;
    const k = kinds[b * 3] >= kinds[b * 3 + 1] && kinds[b * 3] >= kinds[b * 3 + 2] ? 0
      : kinds[b * 3 + 1] >= kinds[b * 3 + 2] ? 1 : 2;
    img.data.set([...colours[k], Math.min(230, 70 + 40 * n)], b * 4);
  }
  const small = document.createElement("canvas");
  small.width = w; small.height = h;
  small.getContext("2d").putImageData(img, 0, 0);
  c.imageSmoothingEnabled = false;
  c.drawImage(small, 0, 0, w * B, h * B);
}

// The features layer is rendered into a cache 1.5 times the map's size when the view rests or
// the features changed (at most twice a second), and only moved and scaled while the operator
// pans and zooms: re-drawing 10^5 outlines every frame would not hold the frame rate.
function drawFeatureCache(now, t) {
  const restful = now - frame.viewChangedAt > 150;
  const stale = featureCache.version !== frame.featuresVersion && now - featureCache.renderedAt > 500;
  const was = featureCache.tView;
  const moved = !was || was.s !== t.s || was.ox !== t.ox || was.oy !== t.oy || was.W !== t.W ||
    was.H !== t.H;
  if ((restful && moved) || stale || !featureCache.t) {
    const c = featureCache.canvas;
    c.width = Math.ceil(t.W * 1.5); c.height = Math.ceil(t.H * 1.5);
    // The cache's own transform: the map's, shifted by a quarter of the map either way.
    const ct = { ...t, ox: t.ox - t.W * 0.25 * t.s, oy: t.oy - t.H * 0.25 * t.s };
    const g = c.getContext("2d");
    g.clearRect(0, 0, c.width, c.height);
    paintFeatures(g, ct, ct.ox, ct.oy, ct.ox + c.width * t.s, ct.oy + c.height * t.s);
    featureCache.t = ct; featureCache.tView = t; featureCache.version = frame.featuresVersion;
    featureCache.renderedAt = now;
  }
  const ct = featureCache.t, k = ct.s / t.s;
  ctx.drawImage(featureCache.canvas, (ct.ox - t.ox) / t.s, (ct.oy - t.oy) / t.s,
                featureCache.canvas.width * k, featureCache.canvas.height * k);
}

// The vehicles in view: each as an oriented marker in its owner's colour (dead: grey with a red
// cross) while they are few enough to leave the ground readable; otherwise one square per cell
// of the screen a small opaque square (2 to 6 pixels of a 14-pixel cell, by the count) in the
// colour of the owner with most vehicles there, with a red dot when any of them is dead: the
// relief shows around the glyphs, and the features are drawn over them.
// `under` draws the features: before the markers, after the cells' glyphs.
let visibleSlots = new Uint32Array(1024);
function drawVehicles(t, under) {
  const tb = state.vehicles, X = tb.x, Z = tb.z, used = tb.used, sz = state.size_z;
  if (visibleSlots.length < tb.cap) visibleSlots = new Uint32Array(tb.cap);
  const vis = visibleSlots;
  let n = 0;
  const x0 = t.ox, y0 = t.oy, x1 = t.ox + t.W * t.s, y1 = t.oy + t.H * t.s;
  for (let s = 0; s < tb.end; ++s) {
    if (!used[s]) continue;
    const y = sz - Z[s];
    if (X[s] >= x0 && X[s] <= x1 && y >= y0 && y <= y1) vis[n++] = s;
  }
  const cover = n * MARKER_PX * MARKER_PX * 1.4 / (t.W * t.H);
  const drawn = { mode: "markers", vehicles: n, marks: 0, dead: 0 };
  if (n <= MARKERS_MAX && cover <= MARKER_COVER_MAX) {
    under();
    const byOwner = new Map(), dead = new Path2D(), crosses = new Path2D();
    const s = MARKER_PX;
    for (let i = 0; i < n; ++i) {
      const v = vis[i];
      const x = (X[v] - t.ox) / t.s, y = (sz - Z[v] - t.oy) / t.s;
      const c = Math.cos(-tb.heading[v]), k = Math.sin(-tb.heading[v]);
      let path = dead;
      if (tb.alive[v]) {
        path = byOwner.get(tb.owner[v]);
        if (!path) { path = new Path2D(); byOwner.set(tb.owner[v], path); }
      } else {
        crosses.moveTo(x - s, y - s); crosses.lineTo(x + s, y + s);
        crosses.moveTo(x - s, y + s); crosses.lineTo(x + s, y - s);
        ++drawn.dead;
      }
      path.moveTo(x + s * c, y + s * k);
      path.lineTo(x - s * 0.7 * c - s * 0.6 * k, y - s * 0.7 * k + s * 0.6 * c);
      path.lineTo(x - s * 0.7 * c + s * 0.6 * k, y - s * 0.7 * k - s * 0.6 * c);
      path.closePath();
    }
    ctx.lineWidth = 1; ctx.strokeStyle = "#000";
    for (const [owner, path] of byOwner) {
      ctx.fillStyle = css(ownerRgb(tb.owners[owner])); ctx.fill(path); ctx.stroke(path);
    }
    ctx.fillStyle = "#666"; ctx.fill(dead); ctx.stroke(dead);
    ctx.strokeStyle = "#ff3b2b"; ctx.lineWidth = 2; ctx.stroke(crosses);
    drawn.marks = n;
  } else {
    drawn.mode = "cells";
    // Counts per cell and owner in typed arrays: no allocation per vehicle at 30 000 a frame.
    const cols = Math.ceil(t.W / CELL_PX), rows = Math.ceil(t.H / CELL_PX);
    const k = tb.owners.length, counts = new Uint32Array(cols * rows * k);
    const totals = new Uint32Array(cols * rows), dead = new Uint32Array(cols * rows);
    for (let i = 0; i < n; ++i) {
      const v = vis[i];
      const ci = Math.min(cols - 1, Math.floor((X[v] - t.ox) / t.s / CELL_PX)),
            cj = Math.min(rows - 1, Math.floor((sz - Z[v] - t.oy) / t.s / CELL_PX));
      const cell = cj * cols + ci;
      ++totals[cell];
      ++counts[cell * k + tb.owner[v]];
      if (!tb.alive[v]) ++dead[cell];
    }
    let most = 1;
    for (let c = 0; c < totals.length; ++c) most = Math.max(most, totals[c]);
    const byOwner = tb.owners.map(() => new Path2D()), deadMarks = new Path2D();
    let cells = 0;
    // Features as a density picture (too many to draw one by one) would hide every glyph: under
    // them then; features as shapes go above the glyphs.
    const featuresFirst = featuresOnCanvas() && featureCache.mode === "density";
    if (featuresFirst) under();
    for (let c = 0; c < totals.length; ++c) {
      if (!totals[c]) continue;
      ++cells;
      let owner = 0;
      for (let o = 1; o < k; ++o) if (counts[c * k + o] > counts[c * k + owner]) owner = o;
      // A square of 2 to GLYPH_MAX_PX pixels, by the square root of the count: at most a fifth of
      // the cell, so the relief and the features stay readable however dense the vehicles.
      const side = Math.round(2 + (GLYPH_MAX_PX - 2) * Math.sqrt(totals[c] / most));
      const x = (c % cols) * CELL_PX + Math.round((CELL_PX - side) / 2),
            y = Math.floor(c / cols) * CELL_PX + Math.round((CELL_PX - side) / 2);
      byOwner[owner].rect(x, y, side, side);
      if (dead[c]) { deadMarks.rect(x + side, y - 2, 2, 2); drawn.dead += dead[c]; }
    }
    tb.owners.forEach((o, i) => { ctx.fillStyle = css(ownerRgb(o)); ctx.fill(byOwner[i]); });
    ctx.fillStyle = "#ff3b2b"; ctx.fill(deadMarks);
    drawn.marks = cells;
    if (!featuresFirst) under();  // the features above the glyphs (docs/view.md "Drawing at scale")
  }
  return drawn;
}
function drawSelected(t) {
  const f = state.selected && state.features.get(state.selected);
  if (!f || !featuresOnCanvas()) return;
  const r = Math.max((f.radius || f.length || f.span || 10) / t.s, 6);
  ctx.strokeStyle = "#ffff00"; ctx.lineWidth = 3;
  ctx.beginPath(); ctx.arc((f.x - t.ox) / t.s, (Y(f.z) - t.oy) / t.s, r, 0, 2 * Math.PI); ctx.stroke();
}
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

function ago(ms) { return ms < 0 ? "never" : `${(ms / 1000).toFixed(1)} s`; }
function drawProcesses() {
  const body = $("processes").querySelector("tbody");
  body.replaceChildren();
  // Equal digests look alike; the server's (else the most common) is the exercise's.
  const counts = {};
  for (const p of state.processes) if (p.reachable) counts[p.digest] = (counts[p.digest] || 0) + 1;
  const server = state.processes.find((p) => p.role === "server" && p.reachable);
  const agreed = server ? server.digest
    : Object.keys(counts).sort((a, b) => counts[b] - counts[a])[0];
  for (const p of state.processes) {
    const tr = document.createElement("tr");
    // Silent is the protocol's verdict (no PDU for silence_ms); a process heard but whose
    // control socket does not answer is "unreachable".
    const st = p.silent ? "silent" : !p.reachable ? "unreachable" : "live";
    const differs = p.reachable && p.digest !== agreed;
    tr.className = `${st}${p.diverged || differs ? " diverged" : ""}`;
    tr.dataset.name = p.name;
    tr.dataset.state = st;
    tr.dataset.diverged = p.diverged || differs ? "1" : "0";
    const c = p.counters || {};
    const cells = [
      `<span class="swatch" style="background:${ownerColour(p.name)}"></span>${p.name}`,
      p.role, p.reachable ? (p.signed_on ? "yes" : "no") : "-",
      p.reachable ? (p.caught_up ? "yes" : "no") : "-",
      p.reachable ? `<span class="swatch" style="background:${digestColour(p.digest)}"></span>` +
        `${p.digest.slice(0, 8)}${p.diverged ? " DIVERGED" : differs ? " differs" : ""}` : "-",
      p.reachable ? p.features : "-",
      p.reachable ? `${c.sent ?? 0} / ${c.received ?? 0}` : "-",
      `${ago(p.last_heard_ago_ms)}${st === "silent" ? " SILENT" : ""}` +
        `${st === "unreachable" ? " NO ANSWER" : ""}`,
    ];
    tr.innerHTML = cells.map((c, i) => `<td${i === 4 ? ' class="digest"' : ""}>${c}</td>`).join("");
    body.appendChild(tr);
  }
}

function describe(e) {
  const t = new Date(e.t_ms).toISOString().slice(11, 23);
  if (e.feature) return `${t} ${e.by} ${e.kind} ${e.feature}` +
    (e.change_seq ? ` (change ${e.change_seq})` : "");
  return `${t} ${e.by} ${e.kind}`;
}
function addEvents(events) {
  const list = $("events");
  for (const e of events) {
    const li = document.createElement("li");
    li.textContent = describe(e);
    li.dataset.kind = e.kind;
    if (!e.feature) li.className = "process";
    list.prepend(li);
  }
  while (list.children.length > 500) list.lastChild.remove();
}

// The feature under a click when features are on the canvas: the nearest whose extent (a
// crater's radius, a berm's or bridge's length) holds the point, or within 8 pixels of it.
function featureAt(ev) {
  const [x, y, scale] = toMap(ev);
  let best = null, bestD = Infinity;
  for (const f of state.features.values()) {
    const d = Math.hypot(f.x - x, Y(f.z) - y);
    const reach = Math.max(f.radius || f.length || f.span || 0, 8 * scale);
    if (d <= reach && d < bestD) { best = f.id; bestD = d; }
  }
  return best;
}
function select(id) {
  const old = $("features").querySelector(".selected");
  if (old) old.classList.remove("selected");
  state.selected = id;
  const g = id && $("features").querySelector(`[data-id="${id}"]`);
  if (g) g.classList.add("selected");
  frame.dirty = true;
  showFeature();
}
function showFeature() {
  const f = state.selected && state.features.get(state.selected);
  $("op-destroy").disabled = !f;
  $("op-breach").disabled = !f || f.type !== "berm";
  if (!f) { $("feature").textContent = "click a feature on the map"; return; }
  const fields = Object.entries(f).filter(([k]) => k !== "history")
    .map(([k, v]) => `${k}: ${typeof v === "number" ? +v.toFixed(3) : v}`).join("\n");
  const history = (f.history || []).map(describe).join("\n");
  $("feature").innerHTML = "";
  const pre = document.createElement("pre");
  pre.id = "feature-fields";
  pre.textContent = `${fields}\n\nhistory:\n${history}`;
  $("feature").appendChild(pre);
}

// Features go to the SVG while they are few (each clickable, styled by CSS) and to the canvas
// when there are more than FEATURE_SVG_MAX; crossing that number moves them all.
let svgFeatures = true;
function applyFeatures(list) {
  for (const f of list) state.features.set(f.id, f);
  if (svgFeatures !== !featuresOnCanvas()) {
    svgFeatures = !featuresOnCanvas();
    $("features").replaceChildren();
    for (const f of state.features.values()) drawFeature(f);
  } else {
    for (const f of list) drawFeature(f);
  }
  ++frame.featuresVersion; frame.dirty = true;
}
function setRelief(version) {
  if (version < 0) return;
  const img = $("relief");
  img.setAttribute("href", `/relief.png?v=${version}`);
  for (const [k, v] of [["x", 0], ["y", 0], ["width", state.size_x], ["height", state.size_z]]) {
    img.setAttribute(k, v);
  }
}

function onSnapshot(s) {
  state.exercise = s.exercise;
  state.size_x = s.exercise.size_x_m;
  state.size_z = s.exercise.size_z_m;
  $("exercise").textContent = `${s.exercise.name} (${s.exercise.view})`;
  if (!state.view) state.view = { x: 0, y: 0, w: state.size_x, h: state.size_z };
  applyView();
  $("features").replaceChildren();
  state.features.clear();
  svgFeatures = true;
  applyFeatures(s.features);
  $("events").replaceChildren();
  addEvents(s.events);
  state.processes = s.processes;
  processesDirty = true;
  state.vehicles.clear();
  s.vehicles.forEach(setVehicle);
  frame.dirty = true;
  setRelief(s.relief);
  ++window.dtView.terrainVersion;
  if (s.exercise.commands) setUpOperator(s.exercise.nodes);
  window.dtView.snapshotAt = Date.now();
}
function onDelta(d) {
  if (d.removed) d.removed.forEach(removeFeature);
  if (d.features) applyFeatures(d.features);
  if (d.events) addEvents(d.events);
  if (d.processes) { state.processes = d.processes; processesDirty = true; }
  if (d.vehicles_removed) d.vehicles_removed.forEach(removeVehicle);
  if (d.vehicles) d.vehicles.forEach(setVehicle);
  if (d.relief !== undefined) setRelief(d.relief);
  // The 3D view asks for its terrain window again (the ground or a feature changed).
  if (d.removed || d.features || d.relief !== undefined) ++window.dtView.terrainVersion;
  window.dtView.deltas++;
}
// Messages are queued as they arrive and applied once per animation frame, all of them at once:
// a vehicle moved by several queued deltas is drawn once, at its latest place, and the page's
// work per frame does not grow with the message rate (docs/view.md "Drawing at scale").
const inbox = [];
let processesDirty = false;
function onMessage(ev) {
  inbox.push(ev.data);
  window.dtView.wsBytes += typeof ev.data === "string" ? ev.data.length : ev.data.byteLength;
}
// The binary vehicle message: the moves of vehicles the page knows, by slot.
function applyVehicleFrame(buf) {
  const h = state.vehicles.applyFrame(buf);
  if (!h) return;
  frame.dirty = true;
  window.dtView.deltas++;
  window.dtView.appliedSeq = Math.max(window.dtView.appliedSeq, h.seq);
  noteLag(h.t_ms);
}
function noteLag(t_ms) {
  const lag = Date.now() - t_ms;
  window.dtView.lagMs = lag;
  window.dtView.maxLagMs = Math.max(window.dtView.maxLagMs || 0, lag);
}
function applyMessage(m) {
  if (m.type === "snapshot") onSnapshot(m);
  else if (m.type === "delta") onDelta(m);
  else if (m.type === "reply") {
    $("op-reply").textContent = `${m.ok ? "ok" : "refused"}: ${m.line || ""} ${m.text}`;
    window.dtView.lastReply = m;
  }
  if (m.seq !== undefined) window.dtView.appliedSeq = m.seq;
  if (m.t_ms !== undefined) noteLag(m.t_ms);
}
function tick(now) {
  const cost = window.dtView.cost;
  const t0 = performance.now();
  if (inbox.length) {
    const batch = inbox.splice(0, inbox.length);
    for (const m of batch) {
      if (typeof m === "string") applyMessage(JSON.parse(m));
      else applyVehicleFrame(m);
    }
    cost.messages += batch.length;
    if (processesDirty) { drawProcesses(); processesDirty = false; }
    $("stats").textContent = `${state.features.size} features, ${state.vehicles.size} vehicles,` +
      ` message ${window.dtView.appliedSeq}, ${window.dtView.lagMs} ms after it was sent`;
  }
  // A resting view whose feature cache is older than the view is drawn once more.
  const cacheBehind = featuresOnCanvas() && (featureCache.version !== frame.featuresVersion ||
    featureCache.tView !== undefined && now - frame.viewChangedAt > 150 &&
    featureCache.renderedAt < frame.viewChangedAt);
  const t1 = performance.now();
  // Under the 3D view the map is not drawn: it is drawn when it shows again.
  const under3d = window.dtView3d && window.dtView3d.on;
  if ((frame.dirty || cacheBehind) && state.view && !under3d) {
    frame.dirty = false;
    drawFrame(now);
    ++cost.draws;
  }
  cost.applyMs += t1 - t0;
  cost.drawMs += performance.now() - t1;
  ++window.dtView.frames;
  requestAnimationFrame(tick);
}
requestAnimationFrame(tick);
function connect() {
  const ws = new WebSocket(`ws://${location.host}/ws`);
  ws.binaryType = "arraybuffer";
  state.ws = ws;
  ws.onopen = () => { $("connection").textContent = "live"; $("connection").className = "good"; };
  ws.onmessage = onMessage;
  ws.onclose = () => {
    $("connection").textContent = "disconnected, retrying";
    $("connection").className = "bad";
    setTimeout(connect, 1000);
  };
}

// ---- pan and zoom: the SVG viewBox in metres ----
function applyView() {
  const v = state.view;
  $("map").setAttribute("viewBox", `${v.x} ${v.y} ${v.w} ${v.h}`);
  frame.dirty = true;
  frame.viewChangedAt = performance.now();
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

// ---- operator actions (only when dt_view runs with --allow-commands) ----
function send(m) {
  m.req = ++state.req;
  state.ws.send(JSON.stringify(m));
}
function setUpOperator(nodes) {
  $("operator").hidden = false;
  const sel = $("op-node");
  if (sel.options.length === 0) {
    for (const n of nodes) { const o = document.createElement("option"); o.textContent = n; sel.appendChild(o); }
  }
}
$("map").addEventListener("click", (ev) => {
  if (drag && drag.moved) return;
  const tool = $("op-tool").value;
  if (!tool || !state.exercise || !state.exercise.commands) {
    select(featuresOnCanvas() ? featureAt(ev) : null);
    return;
  }
  const [x, y] = toMap(ev), z = state.size_z - y;
  const size = +$("op-size").value, dir = +$("op-dir").value, node = $("op-node").value;
  if (tool === "crater") send({ op: "crater", node, x, z, radius: size });
  if (tool === "berm") send({ op: "berm", node, x, z, dir_deg: dir, length: size, width: 4, height: 2 });
  if (tool === "bridge") send({ op: "bridge", node, x, z, dir_deg: dir, width: 6, ramp1: 10,
                                span: size, ramp2: 10, h1: 4, h2: 4 });
});
$("op-destroy").addEventListener("click", () => {
  if (state.selected) send({ op: "destroy", node: $("op-node").value, id: state.selected });
});
$("op-breach").addEventListener("click", () => {
  const f = state.selected && state.features.get(state.selected);
  if (f) send({ op: "breach", node: $("op-node").value, id: f.id, gap_start: f.length / 2 - 2,
                gap_width: 4 });
});

connect();
