// Features on the canvas when they are many: batched paths or a density picture, rendered into a
// cache that pans and zooms with the map, a slice of the features a frame; the selected one's
// ring and the feature under a click.
"use strict";
const FEATURE_SVG_MAX = 2000;   // more features than this: drawn on the canvas too
const FEATURE_SHAPES_MAX = 6000;  // more in view than this: a density picture
const FEATURE_SLICE_MS = 6;     // a frame's time for rendering the cache, so messages keep flowing
const CULL_CHUNK = 5000, PAINT_CHUNK = 1000;  // features between two looks at the clock
const DENSITY_BIN_PX = 3;
const featureCache = { canvas: document.createElement("canvas"), spare: document.createElement("canvas"),
                       version: -1, t: null, tView: null, renderedAt: 0, mode: "shapes", job: null };
function featuresOnCanvas() { return state.features.size > FEATURE_SVG_MAX; }

// Features list[from, to) as a few batched paths, in the cache transform t.
function paintShapes(c, t, list, from, to, bridgesOnly) {
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
  for (let i = from; i < to; ++i) {
    const f = list[i], y = Y(f.z);
    if (bridgesOnly && f.type !== "bridge") continue;
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

// The density picture: features counted in 3-pixel bins by kind (craters, berms, the rest) ...
function binFeatures(job, from, to) {
  const { ct: t, kinds, bw, bh } = job, B = DENSITY_BIN_PX;
  for (let n = from; n < to; ++n) {
    const f = job.inView[n];
    const i = Math.floor((f.x - t.ox) / t.s / B), j = Math.floor((Y(f.z) - t.oy) / t.s / B);
    if (i < 0 || j < 0 || i >= bw || j >= bh) continue;
    const k = f.type === "crater" ? 0 : f.type === "berm" || f.type === "berm_line" ? 1 : 2;
    ++kinds[(j * bw + i) * 3 + k];
  }
}
// ... then each bin in the colour of the kind with most features there (craters orange, berms
// sand, the rest blue-grey), more opaque the more it holds; the bridges drawn over it as shapes.
const DENSITY_RGB = [[255, 176, 96], [232, 208, 128], [160, 192, 255]];
function paintDensity(job) {
  const { kinds, bw, bh } = job, B = DENSITY_BIN_PX;
  const img = new ImageData(bw, bh), px = img.data;
  for (let b = 0; b < bw * bh; ++b) {
    const n = kinds[b * 3] + kinds[b * 3 + 1] + kinds[b * 3 + 2];
    if (!n) continue;
    const k = kinds[b * 3] >= kinds[b * 3 + 1] && kinds[b * 3] >= kinds[b * 3 + 2] ? 0
      : kinds[b * 3 + 1] >= kinds[b * 3 + 2] ? 1 : 2;
    const rgb = DENSITY_RGB[k];
    px[b * 4] = rgb[0]; px[b * 4 + 1] = rgb[1]; px[b * 4 + 2] = rgb[2];
    px[b * 4 + 3] = Math.min(230, 70 + 40 * n);
  }
  const small = featureCache.small || (featureCache.small = document.createElement("canvas"));
  small.width = bw; small.height = bh;
  small.getContext("2d").putImageData(img, 0, 0);
  job.g.imageSmoothingEnabled = false;
  job.g.drawImage(small, 0, 0, bw * B, bh * B);
  paintShapes(job.g, job.ct, job.inView, 0, job.inView.length, true);
}

// A render of the cache into the spare canvas, for the map's transform t: the features culled,
// then drawn, a chunk at a time; the cache shown meanwhile is the last one, moved and scaled.
function startRender(now, t) {
  const c = featureCache.spare, w = Math.ceil(t.W * 1.5), h = Math.ceil(t.H * 1.5);
  if (c.width !== w || c.height !== h) { c.width = w; c.height = h; }  // else no new backing store
  // The cache's own transform: the map's, shifted by a quarter of the map either way.
  const ct = { ...t, ox: t.ox - t.W * 0.25 * t.s, oy: t.oy - t.H * 0.25 * t.s };
  const g = c.getContext("2d");
  g.clearRect(0, 0, c.width, c.height);
  // The features as the Map's live iterator: a feature added meanwhile may be drawn, one removed
  // may not; the next render (the version changed) has them right.
  return { c, g, ct, tView: t, version: frame.featuresVersion, started: performance.now(),
           busyMs: 0, slices: 0, features: state.features.values(), at: 0, inView: [],
           phase: "cull", mode: "shapes",
           x0: ct.ox, y0: ct.oy, x1: ct.ox + c.width * t.s, y1: ct.oy + c.height * t.s };
}
// Works on the render until the deadline (performance.now()); true when it is done.
function stepRender(job, deadline) {
  const from = performance.now();
  ++job.slices;
  let done = false;
  while (!done && performance.now() < deadline) {
    if (job.phase === "cull") {
      let n = 0, next = null;
      while (n++ < CULL_CHUNK && !(next = job.features.next()).done) {
        const f = next.value, reach = f.radius || f.length || f.span || 50, y = Y(f.z);
        if (f.x + reach < job.x0 || f.x - reach > job.x1 || y + reach < job.y0 || y - reach > job.y1) continue;
        job.inView.push(f);
      }
      if (!next || !next.done) continue;
      // Too many outlines to draw, or to read: a density picture of all but the bridges.
      job.mode = job.inView.length > FEATURE_SHAPES_MAX ? "density" : "shapes";
      job.phase = "paint"; job.features = null;
      if (job.mode === "density") {
        job.bw = Math.ceil(job.c.width / DENSITY_BIN_PX); job.bh = Math.ceil(job.c.height / DENSITY_BIN_PX);
        job.kinds = new Uint16Array(job.bw * job.bh * 3);
      }
    } else if (job.phase === "paint") {
      const end = Math.min(job.inView.length, job.at + PAINT_CHUNK);
      if (job.mode === "density") binFeatures(job, job.at, end);
      else paintShapes(job.g, job.ct, job.inView, job.at, end, false);
      job.at = end;
      if (end < job.inView.length) continue;
      if (job.mode === "shapes") { done = true; break; }
      job.phase = "picture";
      break;  // the picture in a slice of its own: a pass over every bin and two copies
    } else {
      paintDensity(job);
      done = true;
    }
  }
  job.busyMs += performance.now() - from;
  return done;
}

// The features layer is rendered into a cache 1.5 times the map's size when the view rests or
// the features changed (at most twice a second), and only moved and scaled while the operator
// pans and zooms: re-drawing 10^5 outlines every frame would not hold the frame rate, and
// rendering them in one go held the page (and its messages) for a long frame.
function drawFeatureCache(now, t) {
  const restful = now - frame.viewChangedAt > 150;
  const stale = featureCache.version !== frame.featuresVersion && now - featureCache.renderedAt > 500;
  const was = featureCache.tView;
  const moved = !was || was.s !== t.s || was.ox !== t.ox || was.oy !== t.oy || was.W !== t.W ||
    was.H !== t.H;
  if (!featureCache.job && ((restful && moved) || stale || !featureCache.t)) {
    featureCache.job = startRender(now, t);
  }
  const job = featureCache.job;
  if (job && stepRender(job, performance.now() + FEATURE_SLICE_MS)) {
    featureCache.spare = featureCache.canvas;
    featureCache.canvas = job.c;
    featureCache.t = job.ct; featureCache.tView = job.tView; featureCache.version = job.version;
    featureCache.mode = job.mode; featureCache.renderedAt = now; featureCache.job = null;
    featureCache.renders = (featureCache.renders || 0) + 1;
    featureCache.lastRender = { mode: job.mode, features: job.inView.length, slices: job.slices,
                                busyMs: job.busyMs, ms: performance.now() - job.started };
    noteSlow("dt:feature-cache", job.started, performance.now(),
             `${job.mode}, ${job.slices} slices, ${job.busyMs.toFixed(0)} ms busy`);
  }
  const ct = featureCache.t;
  if (!ct) return;
  const k = ct.s / t.s;
  ctx.drawImage(featureCache.canvas, (ct.ox - t.ox) / t.s, (ct.oy - t.oy) / t.s,
                featureCache.canvas.width * k, featureCache.canvas.height * k);
}
function drawSelected(t) {
  const f = state.selected && state.features.get(state.selected);
  if (!f || !featuresOnCanvas()) return;
  const r = Math.max((f.radius || f.length || f.span || 10) / t.s, 6);
  ctx.strokeStyle = "#ffff00"; ctx.lineWidth = 3;
  ctx.beginPath(); ctx.arc((f.x - t.ox) / t.s, (Y(f.z) - t.oy) / t.s, r, 0, 2 * Math.PI); ctx.stroke();
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
