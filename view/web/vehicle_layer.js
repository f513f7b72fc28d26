// The vehicles on the canvas over the map: oriented markers, or per-cell glyphs where dense.
"use strict";
// One SVG element per vehicle stalls the page at thousands; the canvas is redrawn at most once
// per animation frame, from the page's model (docs/view.md "Drawing at scale").
const MARKER_PX = 7;          // a marker's half length on the screen, whatever the zoom
const CELL_PX = 14;           // an aggregate cell's side
const GLYPH_MAX_PX = 6;       // the largest cell's glyph: (6 / 14)² of the ground at most
const MARKERS_MAX = 3000;     // more visible than this: per-cell counts
const MARKER_COVER_MAX = 0.12;  // nor when markers would cover more of the map than this
function setVehicle(row) { state.vehicles.setRow(row); frame.dirty = true; }
function removeVehicle(id) { state.vehicles.remove(id); frame.dirty = true; }

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
