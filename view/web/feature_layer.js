// Features on the canvas when they are many: batched paths or a density picture, rendered into a
// cache that pans and zooms with the map; the selected one's ring and the feature under a click.
"use strict";
const FEATURE_SVG_MAX = 2000;   // more features than this: drawn on the canvas too
const FEATURE_SHAPES_MAX = 6000;  // more in view than this: a density picture
const featureCache = { canvas: document.createElement("canvas"), version: -1, t: null,
                       renderedAt: 0 };
function featuresOnCanvas() { return state.features.size > FEATURE_SVG_MAX; }

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
    const started = performance.now();
    const c = featureCache.canvas;
    c.width = Math.ceil(t.W * 1.5); c.height = Math.ceil(t.H * 1.5);
    // The cache's own transform: the map's, shifted by a quarter of the map either way.
    const ct = { ...t, ox: t.ox - t.W * 0.25 * t.s, oy: t.oy - t.H * 0.25 * t.s };
    const g = c.getContext("2d");
    g.clearRect(0, 0, c.width, c.height);
    paintFeatures(g, ct, ct.ox, ct.oy, ct.ox + c.width * t.s, ct.oy + c.height * t.s);
    featureCache.t = ct; featureCache.tView = t; featureCache.version = frame.featuresVersion;
    featureCache.renderedAt = now;
    noteSlow("dt:feature-cache", started, performance.now(), featureCache.mode);
  }
  const ct = featureCache.t, k = ct.s / t.s;
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
