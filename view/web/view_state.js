// The live view page's shared state, colours and the map's frame, which the page's other scripts
// (docs/view.md "Drawing at scale") read and write.
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

// Vehicles are kept in a VehicleTable (vehicle_table.js); a row, as tests read one, is
// [id, owner, type, x, z, heading, speed, alive, slot].
function vehicleOf([id, owner, type, x, z, heading, speed, alive]) {
  return { id, owner, type, x, z, heading, speed, alive };
}
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
// The canvas over the map (vehicles, and features when many) and what asks for its next drawing.
const overlay = $("overlay");
const ctx = overlay.getContext("2d");
const frame = { dirty: true, viewChangedAt: 0, featuresVersion: 0 };

// The map's transform, as the SVG's viewBox (xMidYMid meet) has it: metres per pixel and the
// map point at the canvas's top left.
function transform() {
  const W = overlay.clientWidth, H = overlay.clientHeight, v = state.view;
  const s = Math.max(v.w / W, v.h / H);
  return { W, H, s, ox: v.x + (v.w - W * s) / 2, oy: v.y + (v.h - H * s) / 2 };
}
// A step of the page slower than a frame at 50 Hz, as a performance measure (the browser's
// performance timeline, beside its long tasks): what held the page when it fell behind.
const SLOW_MS = 20;
function noteSlow(name, start, end, detail) {
  if (end - start < SLOW_MS) return;
  if (performance.getEntriesByType("measure").length > 1000) performance.clearMeasures();
  performance.measure(name, { start, end, detail });
}
