// The 3D view's geometry, built once per terrain window: the ground's mesh with its level of
// detail, the bridge solids' faces, the vehicle shape, and the camera's matrices.
"use strict";
const dtMesh3d = (function () {
const VEHICLE_L = 7, VEHICLE_W = 3.2, VEHICLE_H = 2.4;  // metres, before the zoom's scale
function norm(v) { const l = Math.hypot(...v); return v.map((c) => c / l); }
function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }

// Column-major 4x4 matrices, as WebGL takes them, written into `out` (a Float32Array(16)): a
// drawn frame allocates none.
function perspective(out, fovy, aspect, near, far) {
  const f = 1 / Math.tan(fovy / 2), nf = 1 / (near - far);
  out.fill(0);
  out[0] = f / aspect; out[5] = f; out[10] = (far + near) * nf; out[11] = -1; out[14] = 2 * far * near * nf;
  return out;
}
function lookAt(out, eye, at) {  // up is +y
  let zx = eye[0] - at[0], zy = eye[1] - at[1], zz = eye[2] - at[2];
  const zl = Math.hypot(zx, zy, zz); zx /= zl; zy /= zl; zz /= zl;
  let xx = zz, xz = -zx;  // (0, 1, 0) x z
  const xl = Math.hypot(xx, xz) || 1; xx /= xl; xz /= xl;
  const yx = zy * xz, yy = zz * xx - zx * xz, yz = -zy * xx;  // z x x
  out[0] = xx; out[1] = yx; out[2] = zx; out[3] = 0;
  out[4] = 0; out[5] = yy; out[6] = zy; out[7] = 0;
  out[8] = xz; out[9] = yz; out[10] = zz; out[11] = 0;
  out[12] = -(xx * eye[0] + xz * eye[2]);
  out[13] = -(yx * eye[0] + yy * eye[1] + yz * eye[2]);
  out[14] = -(zx * eye[0] + zy * eye[1] + zz * eye[2]); out[15] = 1;
  return out;
}
function mul(out, a, b) {
  for (let c = 0; c < 4; ++c) {
    for (let r = 0; r < 4; ++r) {
      let s = 0;
      for (let k = 0; k < 4; ++k) s += a[k * 4 + r] * b[c * 4 + k];
      out[c * 4 + r] = s;
    }
  }
  return out;
}

// The ground: a grid of the window's samples, coloured by height and tinted where earthworks cut
// (craters, ditches: dark earth) or raise it (berms: light earth). Level of detail: every sample
// in the middle half of the window (around the camera's target), every other one beyond it, where
// the ground is far and small on the screen: a software rasteriser's frame follows the triangles.
function groundMesh(w) {
  const { nx, nz, step, x0, z0, h, d } = w;
  const verts = new Float32Array(nx * nz * 9);
  let lo = Infinity, hi = -Infinity;
  for (const e of h) { lo = Math.min(lo, e); hi = Math.max(hi, e); }
  const span = Math.max(hi - lo, 1);
  const at = (i, j) => h[Math.min(nz - 1, Math.max(0, j)) * nx + Math.min(nx - 1, Math.max(0, i))];
  for (let j = 0; j < nz; ++j) {
    for (let i = 0; i < nx; ++i) {
      const k = (j * nx + i) * 9, e = h[j * nx + i], dd = d[j * nx + i];
      const n = norm([(at(i - 1, j) - at(i + 1, j)) / (2 * step), 1, (at(i, j - 1) - at(i, j + 1)) / (2 * step)]);
      const t = (e - lo) / span;
      let c = [0.32 + 0.28 * t, 0.46 + 0.18 * t, 0.24 + 0.14 * t];
      if (dd < -0.05) c = mix(c, [0.36, 0.25, 0.16], Math.min(1, -dd / 1.5));
      else if (dd > 0.05) c = mix(c, [0.78, 0.66, 0.44], Math.min(1, dd / 1.0));
      verts.set([x0 + i * step, e, z0 + j * step, n[0], n[1], n[2], c[0], c[1], c[2]], k);
    }
  }
  // The coarse lines: every other sample, and the last; the fine block between two of them on
  // each axis, a quarter of the window either side of the target.
  const lines = (n) => { const l = []; for (let i = 0; i < n; i += 2) l.push(i); if (l[l.length - 1] !== n - 1) l.push(n - 1); return l; };
  const xs = lines(nx), zs = lines(nz);
  const block = (lines, n, centre) => {
    const near = (v) => lines.reduce((b, l) => (Math.abs(l - v) < Math.abs(b - v) ? l : b), lines[0]);
    return [near(centre - (n - 1) / 4), near(centre + (n - 1) / 4)];
  };
  const [fi0, fi1] = block(xs, nx, ((w.cx ?? x0 + (nx - 1) * step / 2) - x0) / step);
  const [fj0, fj1] = block(zs, nz, ((w.cz ?? z0 + (nz - 1) * step / 2) - z0) / step);
  const fine = (i, j) => i >= fi0 && i < fi1 && j >= fj0 && j < fj1;
  const idx = [];
  const quad = (i0, j0, i1, j1) => {
    const a = j0 * nx + i0, b = j0 * nx + i1, c = j1 * nx + i0, e = j1 * nx + i1;
    idx.push(a, c, b, b, c, e);
  };
  for (let b = 0; b + 1 < zs.length; ++b) {
    for (let a = 0; a + 1 < xs.length; ++a) {
      if (!fine(xs[a], zs[b])) { quad(xs[a], zs[b], xs[a + 1], zs[b + 1]); continue; }
      for (let j = zs[b]; j < zs[b + 1]; ++j) for (let i = xs[a]; i < xs[a + 1]; ++i) quad(i, j, i + 1, j + 1);
    }
  }
  // No cracks: a fine sample on the block's edge between two coarse ones lies on their line.
  const y = (i, j) => verts[(j * nx + i) * 9 + 1];
  const onLine = (i, j, ia, ja, ib, jb) => { verts[(j * nx + i) * 9 + 1] = (y(ia, ja) + y(ib, jb)) / 2; };
  for (let i = fi0 + 1; i < fi1; i += 2) {
    if (fj0 > 0) onLine(i, fj0, i - 1, fj0, i + 1, fj0);
    if (fj1 < nz - 1) onLine(i, fj1, i - 1, fj1, i + 1, fj1);
  }
  for (let j = fj0 + 1; j < fj1; j += 2) {
    if (fi0 > 0) onLine(fi0, j, fi0, j - 1, fi0, j + 1);
    if (fi1 < nx - 1) onLine(fi1, j, fi1, j - 1, fi1, j + 1);
  }
  return { verts, idx: new Uint32Array(idx), triangles: idx.length / 3 };
}
function mix(a, b, t) { return a.map((v, k) => v + (b[k] - v) * t); }

// A bridge solid (vehicle/bridge_solids.h Solid) as its six faces, flat-shaded: the same boxes
// render/bridge_mesh draws and the vehicles drive on.
const BRIDGE_RGB = { deck: [0.72, 0.72, 0.70], pier: [0.55, 0.55, 0.53], rubble: [0.42, 0.36, 0.32] };
function solidFaces(s, verts, idx) {
  const [ox, oz] = s.o, [ux, uz] = s.u;
  const P = (a, r, top) => {
    const first = a === s.a[0];
    const y = top ? (first ? s.top[0] : s.top[1]) : (first ? s.bottom[0] : s.bottom[1]);
    return [ox + a * ux + r * uz, y, oz + a * uz - r * ux];
  };
  const [a0, a1] = s.a, [r0, r1] = s.r;
  const t00 = P(a0, r0, 1), t10 = P(a1, r0, 1), t11 = P(a1, r1, 1), t01 = P(a0, r1, 1);
  const b00 = P(a0, r0, 0), b10 = P(a1, r0, 0), b11 = P(a1, r1, 0), b01 = P(a0, r1, 0);
  const c = BRIDGE_RGB[s.kind] || BRIDGE_RGB.deck;
  const quad = (p, q, r, t) => {
    // The face's normal from its corners, in the terrain's frame (z north).
    const n = norm(cross(sub(q, p), sub(r, p)));
    const base = verts.length / 9;
    for (const v of [p, q, r, t]) verts.push(v[0], v[1], v[2], n[0], n[1], n[2], c[0], c[1], c[2]);
    idx.push(base, base + 1, base + 2, base, base + 2, base + 3);
  };
  quad(t00, t10, t11, t01); quad(b00, b01, b11, b10);
  quad(t00, b00, b10, t10); quad(t01, t11, b11, b01);
  quad(t00, t01, b01, b00); quad(t10, b10, b11, t11);
}

// A vehicle: a hull and a smaller turret, 1 long along +x (its heading), white (tinted by owner).
function vehicleShape() {
  const verts = [], idx = [];
  const box = (x0, x1, y0, y1, w, shade) => {
    const s = { o: [0, 0], u: [1, 0], a: [x0, x1], r: [-w / 2, w / 2], bottom: [y0, y0], top: [y1, y1], kind: "v" };
    const before = verts.length;
    solidFaces(s, verts, idx);
    for (let k = before; k < verts.length; k += 9) verts[k + 6] = verts[k + 7] = verts[k + 8] = shade;
  };
  box(-VEHICLE_L / 2, VEHICLE_L / 2, 0, VEHICLE_H * 0.55, VEHICLE_W, 1.0);
  box(-VEHICLE_L * 0.15, VEHICLE_L * 0.3, VEHICLE_H * 0.55, VEHICLE_H, VEHICLE_W * 0.6, 0.8);
  box(VEHICLE_L * 0.3, VEHICLE_L * 0.75, VEHICLE_H * 0.72, VEHICLE_H * 0.82, 0.35, 0.6);  // gun
  // solidFaces writes z as the terrain's north: the vertex shader flips it with the rest.
  return { verts: new Float32Array(verts), idx: new Uint32Array(idx) };
}

return { VEHICLE_H, perspective, lookAt, mul, groundMesh, solidFaces, vehicleShape };
})();
