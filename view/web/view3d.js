// The live view's 3D view (docs/view.md "The 3D view"): the terrain window dt_view sends
// (GET /terrain3d: surface heights, earthworks, bridge solids) and the page's vehicles, in
// perspective, drawn with plain WebGL 2.
"use strict";
(function () {
const SKY = [0.53, 0.66, 0.80];
const SUN = norm([0.45, 0.8, 0.35]);
const POSTS = 129;            // samples per side asked of dt_view (it sends at most 257)
const REFETCH_MS = 500;       // a changed terrain is asked again at most this often
const NEAR_MAX = 250;         // vehicles drawn as shapes at most: the nearest; the rest as points
const NEAR_M = 600;           // and only those nearer the eye than this, when there are more
const VEHICLE_REDRAW_MS = 100;  // a frame for the vehicles' moves alone at most this often
const MAX_PIXELS = 250000;    // the canvas's backing store at most: a CPU rasteriser's fill rate
const HIDDEN_Y = -1e9;        // an instance not drawn (no vehicle in its slot, or off the window)
const VEHICLE_L = 7, VEHICLE_W = 3.2, VEHICLE_H = 2.4;  // metres, before the zoom's scale
const v3 = {
  on: false, gl: null, cam: { x: 500, z: 500, yaw: 0.6, pitch: 0.55, dist: 600, follow: null },
  win: null, fetching: false, fetchedAt: 0, terrainVersion: -1, vehiclesAt: -1,
  frames: 0, fps: 0, key: new Float64Array(9), drawnKey: new Float64Array(9).fill(NaN), drawn: { posts: 0, solids: 0, vehicles: 0 }, windows: 0, error: null,
};
window.dtView3d = v3;
const $ = (id) => document.getElementById(id);

function norm(v) { const l = Math.hypot(...v); return v.map((c) => c / l); }
function cross(a, b) { return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]; }
function sub(a, b) { return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]; }
function dot(a, b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
// Column-major 4x4 matrices, as WebGL takes them.
function perspective(fovy, aspect, near, far) {
  const f = 1 / Math.tan(fovy / 2), nf = 1 / (near - far);
  return [f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) * nf, -1, 0, 0, 2 * far * near * nf, 0];
}
function lookAt(eye, at, up) {
  const z = norm(sub(eye, at)), x = norm(cross(up, z)), y = cross(z, x);
  return [x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0,
          -dot(x, eye), -dot(y, eye), -dot(z, eye), 1];
}
function mul(a, b) {
  const o = new Array(16).fill(0);
  for (let c = 0; c < 4; ++c) for (let r = 0; r < 4; ++r)
    for (let k = 0; k < 4; ++k) o[c * 4 + r] += a[k * 4 + r] * b[c * 4 + k];
  return o;
}

// The terrain's frame is x east, z north, y up (docs/conventions.md): GL's z is the terrain's -z,
// so the picture is not mirrored.
const VS = `#version 300 es
uniform mat4 mvp; uniform float scale; uniform float pointPx; uniform vec3 eye; uniform float nearM;
in vec3 pos; in vec3 nrm; in vec3 col;
in vec4 inst; in vec3 instCol;  // vehicles: x, y, z, heading; colour (zero for the meshes)
out vec3 vCol; out float vLight;
void main() {
  vec3 p = pos, n = nrm, c = col;
  if (inst.y < ${HIDDEN_Y / 2}.0 || pointPx > 0.0 &&
      distance(vec3(inst.x, inst.y, -inst.z), eye) < nearM) {  // not drawn, or drawn as a shape
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);
    gl_PointSize = 0.0;
    vCol = vec3(0.0); vLight = 0.0;
    return;
  }
  if (pointPx > 0.0) {  // a vehicle as one point: its place, lifted by its height
    gl_Position = mvp * vec4(inst.x, inst.y + scale * ${VEHICLE_H}, -inst.z, 1.0);
    gl_PointSize = pointPx;
    vCol = instCol;
    vLight = 1.0;
    return;
  }
  if (scale > 0.0) {
    float ch = cos(inst.w), sh = sin(inst.w);
    p = vec3(inst.x + scale * (p.x * ch - p.z * sh), inst.y + scale * p.y,
             inst.z + scale * (p.x * sh + p.z * ch));
    n = vec3(n.x * ch - n.z * sh, n.y, n.x * sh + n.z * ch);
    c = instCol * col;
  }
  gl_Position = mvp * vec4(p.x, p.y, -p.z, 1.0);
  vCol = c;
  vLight = 0.45 + 0.55 * max(dot(normalize(n), vec3(${SUN[0]}, ${SUN[1]}, ${SUN[2]})), 0.0);
}`;
const FS = `#version 300 es
precision mediump float;
in vec3 vCol; in float vLight; out vec4 outColour;
void main() { outColour = vec4(vCol * vLight, 1.0); }`;

function compile(gl) {
  const prog = gl.createProgram();
  for (const [type, text] of [[gl.VERTEX_SHADER, VS], [gl.FRAGMENT_SHADER, FS]]) {
    const s = gl.createShader(type);
    gl.shaderSource(s, text); gl.compileShader(s);
    if (!gl.getShaderParameter(s, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(s));
    gl.attachShader(prog, s);
  }
  gl.linkProgram(prog);
  if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(prog));
  return prog;
}

// A mesh: interleaved pos, nrm, col (9 floats a vertex), with 32-bit indices.
function upload(gl, verts, idx) {
  const vao = gl.createVertexArray();
  gl.bindVertexArray(vao);
  const vb = gl.createBuffer();
  gl.bindBuffer(gl.ARRAY_BUFFER, vb); gl.bufferData(gl.ARRAY_BUFFER, verts, gl.STATIC_DRAW);
  for (const [name, off] of [["pos", 0], ["nrm", 12], ["col", 24]]) {
    const loc = gl.getAttribLocation(v3.prog, name);
    gl.enableVertexAttribArray(loc); gl.vertexAttribPointer(loc, 3, gl.FLOAT, false, 36, off);
  }
  const ib = gl.createBuffer();
  gl.bindBuffer(gl.ELEMENT_ARRAY_BUFFER, ib); gl.bufferData(gl.ELEMENT_ARRAY_BUFFER, idx, gl.STATIC_DRAW);
  gl.bindVertexArray(null);
  return { vao, vb, ib, count: idx.length };
}
function release(gl, m) {
  if (!m) return;
  gl.deleteVertexArray(m.vao); gl.deleteBuffer(m.vb); gl.deleteBuffer(m.ib);
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

function setUp() {
  const canvas = $("view3d");
  const gl = canvas.getContext("webgl2", { antialias: false, preserveDrawingBuffer: true });
  if (!gl) { v3.error = "this browser has no WebGL 2"; return false; }
  v3.gl = gl;
  v3.prog = compile(gl);
  v3.loc = {};
  for (const u of ["mvp", "scale", "pointPx", "eye", "nearM"]) v3.loc[u] = gl.getUniformLocation(v3.prog, u);
  const inst = gl.getAttribLocation(v3.prog, "inst"), col = gl.getAttribLocation(v3.prog, "instCol");
  // The shape's vertices, and per instance the vehicle's place and colour: every slot's instance
  // in one buffer (drawn as points), the nearest vehicles' in another (drawn as shapes).
  const shape = vehicleShape();
  const withInstances = (buffer) => {
    const m = upload(gl, shape.verts, shape.idx);
    gl.bindVertexArray(m.vao);
    gl.bindBuffer(gl.ARRAY_BUFFER, buffer);
    gl.enableVertexAttribArray(inst); gl.vertexAttribPointer(inst, 4, gl.FLOAT, false, 28, 0);
    gl.vertexAttribDivisor(inst, 1);
    gl.enableVertexAttribArray(col); gl.vertexAttribPointer(col, 3, gl.FLOAT, false, 28, 16);
    gl.vertexAttribDivisor(col, 1);
    gl.bindVertexArray(null);
    return m;
  };
  v3.instances = gl.createBuffer();
  v3.nearInstances = gl.createBuffer();
  v3.near = withInstances(v3.nearInstances);
  // The points: the same buffer read per vertex, not per instance, so all are one plain draw (a
  // CPU rasteriser runs an instanced draw instance by instance: 9000 points took it 130 ms).
  v3.points = gl.createVertexArray();
  gl.bindVertexArray(v3.points);
  gl.bindBuffer(gl.ARRAY_BUFFER, v3.instances);
  gl.enableVertexAttribArray(inst); gl.vertexAttribPointer(inst, 4, gl.FLOAT, false, 28, 0);
  gl.enableVertexAttribArray(col); gl.vertexAttribPointer(col, 3, gl.FLOAT, false, 28, 16);
  gl.bindVertexArray(null);
  return true;
}

// The window's half side for the camera's distance: what the camera sees, bounded so a far view
// of a large terrain gets a coarser step from dt_view, never more samples.
function wantedHalf() { return Math.min(Math.max(v3.cam.dist * 1.8, 120), 40000); }
function needsWindow(now) {
  if (v3.fetching) return false;
  const w = v3.win, tv = window.dtView.terrainVersion || 0;
  if (!w) return true;
  const half = wantedHalf();
  const moved = Math.hypot(v3.cam.x - w.cx, v3.cam.z - w.cz) > w.half / 4;
  const rescaled = half > w.half * 1.5 || half < w.half / 1.5;
  return moved || rescaled || (tv !== v3.terrainVersion && now - v3.fetchedAt > REFETCH_MS);
}
async function fetchWindow(now) {
  v3.fetching = true;
  v3.fetchedAt = now;
  const cx = v3.cam.x, cz = v3.cam.z, half = wantedHalf();
  const tv = window.dtView.terrainVersion || 0;
  try {
    const r = await fetch(`/terrain3d?x=${cx.toFixed(1)}&z=${cz.toFixed(1)}&half=${half.toFixed(0)}&posts=${POSTS}`);
    if (!r.ok) throw new Error(`/terrain3d: ${r.status} ${await r.text()}`);
    const w = await r.json();
    Object.assign(w, { cx, cz, half });
    const gl = v3.gl;
    release(gl, v3.ground); release(gl, v3.bridges);
    const g = groundMesh(w);
    v3.ground = upload(gl, g.verts, g.idx);
    v3.groundTriangles = g.triangles;
    const verts = [], idx = [];
    for (const s of w.solids) solidFaces(s, verts, idx);
    v3.bridges = idx.length ? upload(gl, new Float32Array(verts), new Uint32Array(idx)) : null;
    v3.decks = w.solids.filter((s) => s.kind !== "pier");
    v3.win = w;
    v3.terrainVersion = tv;
    v3.vehiclesAt = -1;
    ++v3.windows;
    v3.error = null;
  } catch (e) {
    v3.error = String(e);
  }
  v3.fetching = false;
}

// Where a vehicle stands: the window's surface under it, or the top of a deck or rubble it is on.
function heightAt(x, z) {
  const w = v3.win;
  const fi = (x - w.x0) / w.step, fj = (z - w.z0) / w.step;
  if (fi < 0 || fj < 0 || fi > w.nx - 1 || fj > w.nz - 1) return null;
  const i = Math.min(Math.floor(fi), w.nx - 2), j = Math.min(Math.floor(fj), w.nz - 2);
  const u = fi - i, t = fj - j, h = w.h, nx = w.nx;
  let y = (h[j * nx + i] * (1 - u) + h[j * nx + i + 1] * u) * (1 - t) +
          (h[(j + 1) * nx + i] * (1 - u) + h[(j + 1) * nx + i + 1] * u) * t;
  if (v3.decks.length <= 64) {
    for (const s of v3.decks) {
      const dx = x - s.o[0], dz = z - s.o[1];
      const a = dx * s.u[0] + dz * s.u[1], r = dx * s.u[1] - dz * s.u[0];
      if (a < s.a[0] || a > s.a[1] || r < s.r[0] || r > s.r[1]) continue;
      y = Math.max(y, s.top[0] + (a - s.a[0]) * (s.top[1] - s.top[0]) / (s.a[1] - s.a[0]));
    }
  }
  return y;
}

// The vehicles as instances (x, y, z, heading, r, g, b), one per slot of the page's vehicle
// table: the slots a message moved are rewritten and the range they span uploaded; the whole
// buffer only when the terrain window (the heights) or the table's size changed.
function instanceOf(tb, s, data, shown) {
  const o = s * 7;
  const y = tb.used[s] ? heightAt(tb.x[s], tb.z[s]) : null;
  const was = shown[s];
  shown[s] = y === null ? 0 : 1;
  v3.vehicleCount += shown[s] - was;
  if (y === null) { data[o + 1] = HIDDEN_Y; return; }
  const c = tb.alive[s] ? window.dtView.ownerRgb(tb.owners[tb.owner[s]]) : [70, 70, 70];
  data[o] = tb.x[s]; data[o + 1] = y; data[o + 2] = tb.z[s]; data[o + 3] = tb.heading[s];
  data[o + 4] = c[0] / 255; data[o + 5] = c[1] / 255; data[o + 6] = c[2] / 255;
}
function updateVehicles() {
  const tb = window.dtView.state.vehicles, gl = v3.gl;
  gl.bindBuffer(gl.ARRAY_BUFFER, v3.instances);
  if (v3.vehiclesAt === -1 || !v3.inst || v3.inst.length !== tb.cap * 7) {
    v3.inst = new Float32Array(tb.cap * 7).fill(HIDDEN_Y);
    v3.shown = new Uint8Array(tb.cap);
    v3.vehicleCount = 0;
    tb.takeChanged(() => {});
    for (let s = 0; s < tb.end; ++s) instanceOf(tb, s, v3.inst, v3.shown);
    gl.bufferData(gl.ARRAY_BUFFER, v3.inst, gl.DYNAMIC_DRAW);
    v3.vehiclesAt = 0;
    v3.uploaded = tb.cap;
    return;
  }
  let lo = Infinity, hi = -1;
  tb.takeChanged((s) => { instanceOf(tb, s, v3.inst, v3.shown); lo = Math.min(lo, s); hi = Math.max(hi, s); });
  if (hi >= lo) {
    gl.bufferSubData(gl.ARRAY_BUFFER, lo * 28, v3.inst, lo * 7, (hi - lo + 1) * 7);
    v3.uploaded += hi - lo + 1;
  }
}

// Level of detail: shapes for the nearest vehicles (all of them while they are NEAR_MAX or fewer),
// points for the rest; returns the radius from the eye inside which vehicles are shapes.
function nearVehicles(eye) {
  const tb = window.dtView.state.vehicles, data = v3.inst, shown = v3.shown;
  const all = v3.vehicleCount <= NEAR_MAX;
  const limit = all ? Infinity : NEAR_M * NEAR_M;
  if (!v3.nearD || v3.nearD.length < tb.cap) {
    v3.nearD = new Float32Array(tb.cap); v3.nearS = new Uint32Array(tb.cap);
  }
  let n = 0;
  for (let s = 0; s < tb.end; ++s) {
    if (!shown[s]) continue;
    const o = s * 7, dx = data[o] - eye[0], dy = data[o + 1] - eye[1], dz = -data[o + 2] - eye[2];
    const d = dx * dx + dy * dy + dz * dz;
    if (d < limit) { v3.nearD[n] = d; v3.nearS[n] = s; ++n; }
  }
  let radius2 = limit;
  if (n > NEAR_MAX) radius2 = v3.nearD.slice(0, n).sort()[NEAR_MAX];
  const near = v3.nearBuf && v3.nearBuf.length >= NEAR_MAX * 7 ? v3.nearBuf
    : (v3.nearBuf = new Float32Array(NEAR_MAX * 7));
  let k = 0;
  for (let i = 0; i < n && k < NEAR_MAX; ++i) {
    if (v3.nearD[i] >= radius2) continue;
    near.set(data.subarray(v3.nearS[i] * 7, v3.nearS[i] * 7 + 7), k * 7);
    ++k;
  }
  const gl = v3.gl;
  gl.bindBuffer(gl.ARRAY_BUFFER, v3.nearInstances);
  gl.bufferData(gl.ARRAY_BUFFER, near.subarray(0, k * 7), gl.DYNAMIC_DRAW);
  v3.nearCount = k;
  return all ? Infinity : Math.sqrt(radius2);
}

function draw(now) {
  if (!v3.on) return;
  requestAnimationFrame(draw);
  const cam = v3.cam;
  if (cam.follow) {
    const r = window.dtView.state.vehicles.get(cam.follow);
    if (r) { cam.x = r[3]; cam.z = r[4]; }
  }
  if (needsWindow(now)) fetchWindow(now);
  const gl = v3.gl, canvas = gl.canvas;
  const W = canvas.clientWidth, H = canvas.clientHeight;
  // Drawn only when something it shows changed (the camera, the window, a vehicle, the size):
  // the work follows the messages and the operator, not the display's rate.
  // The vehicles' moves alone redraw at most every VEHICLE_REDRAW_MS: the page keeps applying its
  // messages (and stays current) however slowly the rasteriser draws.
  const dv = window.dtView;
  // What the picture depends on, compared in place: nothing allocated on a frame not drawn.
  const key = v3.key, was = v3.drawnKey;
  key[0] = cam.x; key[1] = cam.z; key[2] = cam.yaw; key[3] = cam.pitch; key[4] = cam.dist;
  key[5] = v3.windows; key[6] = dv.snapshotAt; key[7] = W; key[8] = H;
  let same = true;
  for (let i = 0; i < key.length; ++i) same = same && key[i] === was[i];
  const moved = dv.deltas !== v3.drawnDeltas && now - (v3.drawnAt || 0) >= VEHICLE_REDRAW_MS;
  if (same && !moved) return;
  was.set(key);
  v3.drawnDeltas = dv.deltas;
  v3.drawnAt = now;
  ++v3.frames;
  if (now - (v3.fpsFrom || 0) >= 1000) {
    v3.fps = v3.fpsFrom ? Math.round((v3.frames - v3.fpsFrames) * 1000 / (now - v3.fpsFrom)) : 0;
    v3.fpsFrom = now; v3.fpsFrames = v3.frames;
  }
  // Fewer pixels than the screen's on a large canvas: the picture scaled up, not a stalled page.
  const k = Math.min(1, Math.sqrt(MAX_PIXELS / Math.max(1, W * H)));
  const PW = Math.round(W * k), PH = Math.round(H * k);
  if (canvas.width !== PW || canvas.height !== PH) { canvas.width = PW; canvas.height = PH; }
  gl.viewport(0, 0, PW, PH);
  gl.clearColor(SKY[0], SKY[1], SKY[2], 1);
  gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
  if (!v3.win) return;
  gl.enable(gl.DEPTH_TEST);
  gl.useProgram(v3.prog);
  const ty = heightAt(cam.x, cam.z) ?? 0;
  const at = [cam.x, ty, -cam.z];
  const eye = [at[0] - cam.dist * Math.cos(cam.pitch) * Math.sin(cam.yaw),
               at[1] + cam.dist * Math.sin(cam.pitch),
               at[2] + cam.dist * Math.cos(cam.pitch) * Math.cos(cam.yaw)];
  const mvp = mul(perspective(0.9, W / Math.max(H, 1), Math.max(0.5, cam.dist / 200), cam.dist * 8 + 4000),
                  lookAt(eye, at, [0, 1, 0]));
  gl.uniformMatrix4fv(v3.loc.mvp, false, mvp);
  gl.uniform1f(v3.loc.scale, 0);
  gl.uniform1f(v3.loc.nearM, 0);
  gl.uniform3fv(v3.loc.eye, eye);
  for (const m of [v3.ground, v3.bridges]) {
    if (!m) continue;
    gl.bindVertexArray(m.vao);
    gl.drawElements(gl.TRIANGLES, m.count, gl.UNSIGNED_INT, 0);
  }
  updateVehicles();
  const nearM = nearVehicles(eye);
  // Vehicles at their size up close, larger when far so a marker stays a few pixels.
  gl.uniform1f(v3.loc.scale, Math.max(1, cam.dist / 250));
  gl.uniform1f(v3.loc.pointPx, 0);
  if (v3.nearCount) {
    gl.bindVertexArray(v3.near.vao);
    gl.drawElementsInstanced(gl.TRIANGLES, v3.near.count, gl.UNSIGNED_INT, 0, v3.nearCount);
  }
  // The rest as one point each (a shape of 72 vertices each costs a CPU rasteriser too much at
  // thousands); the shader leaves out those inside nearM, drawn as shapes.
  const points = v3.vehicleCount - v3.nearCount;
  if (points > 0) {
    gl.uniform1f(v3.loc.pointPx, 5);
    gl.uniform1f(v3.loc.nearM, nearM === Infinity ? 1e30 : nearM);
    gl.bindVertexArray(v3.points);
    gl.drawArrays(gl.POINTS, 0, window.dtView.state.vehicles.end);
  }
  gl.uniform1f(v3.loc.pointPx, 0);
  gl.bindVertexArray(null);
  v3.drawn = { posts: v3.win.nx * v3.win.nz, step: v3.win.step, solids: v3.win.solids.length,
               triangles: v3.groundTriangles,
               vehicles: v3.vehicleCount, shapes: v3.nearCount, points, pixels: PW * PH };
  $("help3d").textContent = `3D: ${v3.fps} fps, ${v3.win.nx}×${v3.win.nz} posts every ` +
    `${v3.win.step} m, ${v3.win.solids.length} bridge solids, ${v3.vehicleCount} vehicles` +
    (cam.follow ? `, following ${cam.follow}` : "") + (v3.error ? ` (${v3.error})` : "");
}

function show(on) {
  if (on && !v3.gl && !setUp()) { $("help3d").textContent = v3.error; }
  v3.on = on && !!v3.gl;
  v3.drawnKey.fill(NaN);  // drawn at once
  v3.vehiclesAt = -1;  // the table's moves were not followed while hidden
  $("mapbox").classList.toggle("three", v3.on);
  $("toggle3d").textContent = v3.on ? "2D" : "3D";
  if (v3.on) requestAnimationFrame(draw);
}
// Opening on the 2D view's centre, unless the address says where (#3d=x,z,yaw,pitch,dist and
// &follow=<vehicle id>: a fixed camera for tests and for a link to a place).
function open() {
  const st = window.dtView.state;
  if (st.view) {
    v3.cam.x = st.view.x + st.view.w / 2;
    v3.cam.z = st.size_z - (st.view.y + st.view.h / 2);
    v3.cam.dist = Math.max(100, st.view.w * 0.6);
  }
  show(true);
}
function fromHash() {
  const m = /3d(?:=([-\d.,]+))?/.exec(location.hash);
  if (!m) return;
  if (m[1]) {
    const [x, z, yaw, pitch, dist] = m[1].split(",").map(Number);
    Object.assign(v3.cam, { x, z, yaw, pitch, dist });
  }
  const f = /follow=([^&]+)/.exec(location.hash);
  if (f) v3.cam.follow = decodeURIComponent(f[1]);
  show(true);
}

let drag = null;
function setUpControls() {
  const c = $("view3d");
  c.addEventListener("mousedown", (e) => { drag = { x: e.clientX, y: e.clientY, pan: e.shiftKey || e.button === 2 }; });
  window.addEventListener("mouseup", () => { drag = null; });
  c.addEventListener("contextmenu", (e) => e.preventDefault());
  window.addEventListener("mousemove", (e) => {
    if (!drag || !v3.on) return;
    const dx = e.clientX - drag.x, dy = e.clientY - drag.y, cam = v3.cam;
    drag.x = e.clientX; drag.y = e.clientY;
    if (drag.pan) {
      // Moving the ground under the pointer: the camera's target leaves any vehicle it followed.
      const k = cam.dist / 600;
      cam.x -= k * (dx * Math.cos(cam.yaw) - dy * Math.sin(cam.yaw));
      cam.z -= k * (dx * Math.sin(cam.yaw) + dy * Math.cos(cam.yaw));
      cam.follow = null;
    } else {
      cam.yaw += dx * 0.008;
      cam.pitch = Math.min(1.5, Math.max(0.05, cam.pitch + dy * 0.006));
    }
  });
  c.addEventListener("wheel", (e) => {
    e.preventDefault();
    v3.cam.dist = Math.min(60000, Math.max(15, v3.cam.dist * Math.exp(e.deltaY * 0.001)));
  }, { passive: false });
  $("toggle3d").addEventListener("click", () => (v3.on ? show(false) : open()));
  $("follow").addEventListener("change", (e) => { v3.cam.follow = e.target.value.trim() || null; });
}
setUpControls();
fromHash();
})();
