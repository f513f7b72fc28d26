// The live view's 3D view (docs/view.md "The 3D view"): the terrain window dt_view sends
// (GET /terrain3d: surface heights, earthworks, bridge solids) and the page's vehicles, in
// perspective, drawn with plain WebGL 2.
"use strict";
(function () {
const SKY = [0.53, 0.66, 0.80];
const SUN = [0.45, 0.8, 0.35].map((c, _, v) => c / Math.hypot(...v));
const POSTS = 129;            // samples per side asked of dt_view (it sends at most 257)
const REFETCH_MS = 500;       // a changed terrain is asked again at most this often
const WHOLE_MAX = 250;        // vehicles drawn as whole shapes at most: the nearest
const NEAR_MAX = 500;         // as shapes at most (beyond WHOLE_MAX their hull alone); the rest points
const POINTS_ALL = 12000;     // points drawn all up to this many; beyond, the far ones thinned
const VEHICLE_REDRAW_MS = 100;  // a frame for the vehicles' moves alone at most this often
const MAX_PIXELS = 250000;    // the canvas's backing store at most: a CPU rasteriser's fill rate
const M = dtMesh3d, VEHICLE_H = M.VEHICLE_H;
const v3 = {
  on: false, gl: null, cam: { x: 500, z: 500, yaw: 0.6, pitch: 0.55, dist: 600, follow: null },
  win: null, fetching: false, fetchedAt: 0, terrainVersion: -1, vehiclesAt: -1,
  frames: 0, fps: 0, key: new Float64Array(9), drawnKey: new Float64Array(9).fill(NaN),
  drawn: { posts: 0, solids: 0, vehicles: 0 }, windows: 0, error: null,
  instances: new VehicleInstances(WHOLE_MAX, NEAR_MAX, POINTS_ALL), pendingMove: false,
  // The page's own time in render() (JS and GL calls; with `finish` set, the rasteriser's too).
  cost: { frames: 0, ms: 0, finish: false },
  mats: { proj: new Float32Array(16), view: new Float32Array(16), mvp: new Float32Array(16),
          eye: new Float64Array(3), at: new Float64Array(3) },
};
window.dtView3d = v3;
const $ = (id) => document.getElementById(id);

// The terrain's frame is x east, z north, y up (docs/conventions.md): GL's z is the terrain's -z,
// so the picture is not mirrored.
// Shapes are drawn without instancing: SwiftShader (chromium's WebGL without a GPU) runs an
// instanced draw instance by instance, about 27 us each (2000 shapes of 2 triangles cost as much
// as of 36), so each of SHAPES_PER_DRAW instances' data is a uniform block's entry, the one mesh
// another block, and one plain draw of n x the mesh's vertices finds both by gl_VertexID.
const SHAPES_PER_DRAW = 512;  // 16 kB of instances: the least uniform block size WebGL 2 allows
const vertexShader = (shapeVerts) => `#version 300 es
uniform mat4 mvp; uniform float scale; uniform float pointPx; uniform int mode;  // 0 meshes, 1 shapes, 2 points
uniform int shapeVerts;  // the shape's first vertices drawn: all, or the hull's
layout(std140) uniform Shape { vec4 shapeV[${shapeVerts * 3}]; };  // per vertex: place, normal, shade
layout(std140) uniform Instances { vec4 instV[${SHAPES_PER_DRAW * 2}]; };  // as inst, instCol
in vec3 pos; in vec3 nrm; in vec3 col;
in vec4 inst; in vec4 instCol;  // points: x, y, z, heading; owner's colour, dead (1) or not (0)
out vec3 vCol; out float vLight; out float vDeadPoint;
void main() {
  vDeadPoint = 0.0;
  if (mode == 2) {  // a vehicle as one point: its place, lifted by its height, unlit
    gl_Position = mvp * vec4(inst.x, inst.y + scale * ${VEHICLE_H}, -inst.z, 1.0);
    gl_PointSize = pointPx;
    vCol = instCol.rgb * (instCol.a > 0.5 ? 0.55 : 1.0);
    vDeadPoint = instCol.a;
    vLight = 1.0;
    return;
  }
  vec3 p = pos, n = nrm, c = col;
  if (mode == 1) {  // a vehicle's shape: turned to its heading, tinted by its owner
    int i = gl_VertexID / shapeVerts, v = gl_VertexID - i * shapeVerts;
    vec4 at = instV[2 * i], ic = instV[2 * i + 1];
    p = shapeV[3 * v].xyz; n = shapeV[3 * v + 1].xyz;
    float shade = shapeV[3 * v + 2].x, ch = cos(at.w), sh = sin(at.w);
    p = vec3(at.x + scale * (p.x * ch - p.z * sh), at.y + scale * p.y,
             at.z + scale * (p.x * sh + p.z * ch));
    n = vec3(n.x * ch - n.z * sh, n.y, n.x * sh + n.z * ch);
    // Dead: the hull its owner's colour darkened, the turret and gun burnt.
    c = ic.a < 0.5 ? ic.rgb * shade : shade > 0.9 ? ic.rgb * 0.55 : vec3(0.30, 0.07, 0.04);
  }
  gl_Position = mvp * vec4(p.x, p.y, -p.z, 1.0);
  vCol = c;
  vLight = 0.45 + 0.55 * max(dot(normalize(n), vec3(${SUN[0]}, ${SUN[1]}, ${SUN[2]})), 0.0);
}`;
// A dead vehicle's point has a red centre, as the map's dead markers a red cross.
const FS = `#version 300 es
precision mediump float;
in vec3 vCol; in float vLight; in float vDeadPoint; out vec4 outColour;
void main() {
  vec3 c = vCol * vLight;
  if (vDeadPoint > 0.5 && length(gl_PointCoord - 0.5) < 0.3) c = vec3(1.0, 0.23, 0.17);
  outColour = vec4(c, 1.0);
}`;

function compile(gl, VS) {
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

// The context's attributes (a test may pass others in window.dtView3dContext to compare them):
// no drawing buffer kept after it is shown, which would cost a copy a frame; the tests read the
// pixels through snapshot(), which draws and reads in one task.
function contextAttributes() {
  return Object.assign({ antialias: false, preserveDrawingBuffer: false, depth: true,
                         powerPreference: "high-performance" }, window.dtView3dContext || {});
}
function setUp() {
  const canvas = $("view3d");
  const gl = canvas.getContext("webgl2", contextAttributes());
  if (!gl) { v3.error = "this browser has no WebGL 2"; return false; }
  v3.gl = gl;
  // The shape's vertices unindexed: place, normal and shade, each a vec4 of the Shape block.
  const shape = M.vehicleShape(), sv = new Float32Array(shape.idx.length * 12);
  shape.idx.forEach((k, v) => {
    for (let c = 0; c < 3; ++c) for (let e = 0; e < 3; ++e) sv[v * 12 + c * 4 + e] = shape.verts[k * 9 + c * 3 + e];
  });
  v3.shapeVerts = shape.idx.length;
  v3.prog = compile(gl, vertexShader(v3.shapeVerts));
  v3.loc = {};
  for (const u of ["mvp", "scale", "pointPx", "mode", "shapeVerts"]) v3.loc[u] = gl.getUniformLocation(v3.prog, u);
  gl.uniformBlockBinding(v3.prog, gl.getUniformBlockIndex(v3.prog, "Shape"), 0);
  gl.uniformBlockBinding(v3.prog, gl.getUniformBlockIndex(v3.prog, "Instances"), 1);
  v3.shapeBuffer = gl.createBuffer();
  gl.bindBuffer(gl.UNIFORM_BUFFER, v3.shapeBuffer);
  gl.bufferData(gl.UNIFORM_BUFFER, sv, gl.STATIC_DRAW);
  gl.bindBufferBase(gl.UNIFORM_BUFFER, 0, v3.shapeBuffer);
  // The nearest vehicles' instances (whole shapes, hulls: a buffer each), SHAPES_PER_DRAW a draw
  // (the buffer a whole number of them: a block's range is always full); every block is bound
  // whatever is drawn, as GL asks.
  v3.blockBytes = SHAPES_PER_DRAW * INSTANCE_FLOATS * 4;
  v3.wholeBuffer = { buffer: gl.createBuffer(), bytes: 0 };
  v3.hullBuffer = { buffer: gl.createBuffer(), bytes: 0 };
  gl.bindBuffer(gl.UNIFORM_BUFFER, v3.wholeBuffer.buffer);
  gl.bufferData(gl.UNIFORM_BUFFER, v3.blockBytes, gl.DYNAMIC_DRAW);
  gl.bindBufferRange(gl.UNIFORM_BUFFER, 1, v3.wholeBuffer.buffer, 0, v3.blockBytes);
  // The hull's vertices: the shape's first box.
  v3.hullVerts = 36;
  v3.noAttributes = gl.createVertexArray();
  const inst = gl.getAttribLocation(v3.prog, "inst"), col = gl.getAttribLocation(v3.prog, "instCol");
  const F = INSTANCE_FLOATS * 4;
  // The points: the far vehicles' buffer read per vertex, not per instance, so all are one plain
  // draw (a CPU rasteriser runs an instanced draw instance by instance: 9000 points took it 130 ms).
  v3.farBuffer = gl.createBuffer();
  v3.farBytes = 0;
  v3.points = gl.createVertexArray();
  gl.bindVertexArray(v3.points);
  gl.bindBuffer(gl.ARRAY_BUFFER, v3.farBuffer);
  gl.enableVertexAttribArray(inst); gl.vertexAttribPointer(inst, 4, gl.FLOAT, false, F, 0);
  gl.enableVertexAttribArray(col); gl.vertexAttribPointer(col, 4, gl.FLOAT, false, F, 16);
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
    const g = M.groundMesh(w);
    v3.ground = upload(gl, g.verts, g.idx);
    v3.groundTriangles = g.triangles;
    const verts = [], idx = [];
    for (const s of w.solids) M.solidFaces(s, verts, idx);
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

// The vehicles' instances follow the table's moved slots on every animation frame (no GL
// call: the buffers are filled when a frame is drawn); all slots again when the terrain window
// (the heights) or the table's size changed. Returns whether a vehicle on the window moved.
// Named functions, not closures made per call: nothing allocated on an animation frame.
let movedOnWindow = false;
function followSlot(s) {
  const tb = window.dtView.state.vehicles;
  const y = tb.used[s] ? heightAt(tb.x[s], tb.z[s]) : null;
  if (v3.instances.set(tb, s, y, y === null ? null : window.dtView.ownerRgb(tb.owners[tb.owner[s]]))) {
    movedOnWindow = true;
  }
}
function ignoreSlot() {}
function updateVehicles() {
  const tb = window.dtView.state.vehicles, vi = v3.instances;
  if (!v3.win) return false;
  movedOnWindow = false;
  if (v3.vehiclesAt === -1 || vi.cap !== tb.cap) {
    vi.reset(tb.cap);
    tb.takeChanged(ignoreSlot);
    for (let s = 0; s < tb.end; ++s) followSlot(s);
    v3.vehiclesAt = 0;
    return true;
  }
  tb.takeChanged(followSlot);
  return movedOnWindow;
}

// A uniform buffer of whole blocks holding `data`'s first n instances.
function fillBlocks(b, data, n) {
  if (!n) return;
  const gl = v3.gl, bytes = Math.ceil(data.length / INSTANCE_FLOATS / SHAPES_PER_DRAW) * v3.blockBytes;
  gl.bindBuffer(gl.UNIFORM_BUFFER, b.buffer);
  if (b.bytes !== bytes) { b.bytes = bytes; gl.bufferData(gl.UNIFORM_BUFFER, bytes, gl.DYNAMIC_DRAW); }
  gl.bufferSubData(gl.UNIFORM_BUFFER, 0, data, 0, n * INSTANCE_FLOATS);
}
// n shapes of `verts` vertices each from buffer b, SHAPES_PER_DRAW a draw.
function drawShapes(b, n, verts) {
  const gl = v3.gl;
  gl.uniform1i(v3.loc.shapeVerts, verts);
  for (let from = 0; from < n; from += SHAPES_PER_DRAW) {
    gl.bindBufferRange(gl.UNIFORM_BUFFER, 1, b.buffer, from * INSTANCE_FLOATS * 4, v3.blockBytes);
    gl.drawArrays(gl.TRIANGLES, 0, Math.min(SHAPES_PER_DRAW, n - from) * verts);
  }
}

// The frame's vehicles: the nearest as shapes, the rest as points (the far ones thinned), each
// buffer filled in place and uploaded with bufferSubData; reallocated only when the table grew.
function uploadVehicles(eye) {
  const gl = v3.gl, vi = v3.instances;
  vi.select(window.dtView.state.vehicles.end, eye[0], eye[1], eye[2]);
  fillBlocks(v3.wholeBuffer, vi.whole, vi.wholeCount);
  fillBlocks(v3.hullBuffer, vi.hulls, vi.nearCount - vi.wholeCount);
  if (vi.farCount) {
    gl.bindBuffer(gl.ARRAY_BUFFER, v3.farBuffer);
    if (v3.farBytes !== vi.far.byteLength) {
      v3.farBytes = vi.far.byteLength;
      gl.bufferData(gl.ARRAY_BUFFER, v3.farBytes, gl.DYNAMIC_DRAW);
    }
    gl.bufferSubData(gl.ARRAY_BUFFER, 0, vi.far, 0, vi.farCount * INSTANCE_FLOATS);
  }
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
  if (updateVehicles()) v3.pendingMove = true;
  const gl = v3.gl, canvas = gl.canvas;
  // Drawn only when something it shows changed (the camera, the window, a vehicle on it, the
  // size): the work follows the messages and the operator, not the display's rate, and v3.fps
  // counts the frames drawn when there was something to draw.
  // The vehicles' moves alone redraw at most every VEHICLE_REDRAW_MS: the page keeps applying its
  // messages (and stays current) however slowly the rasteriser draws.
  const dv = window.dtView;
  // What the picture depends on, compared in place: nothing allocated on a frame not drawn.
  const key = v3.key, was = v3.drawnKey;
  key[0] = cam.x; key[1] = cam.z; key[2] = cam.yaw; key[3] = cam.pitch; key[4] = cam.dist;
  key[5] = v3.windows; key[6] = dv.snapshotAt; key[7] = canvas.clientWidth; key[8] = canvas.clientHeight;
  let same = true;
  for (let i = 0; i < key.length; ++i) same = same && key[i] === was[i];
  const moved = v3.pendingMove && now - (v3.drawnAt || 0) >= VEHICLE_REDRAW_MS;
  if (same && !moved) return;
  was.set(key);
  v3.drawnAt = now;
  ++v3.frames;
  if (now - (v3.fpsFrom || 0) >= 1000) {
    v3.fps = v3.fpsFrom ? Math.round((v3.frames - v3.fpsFrames) * 1000 / (now - v3.fpsFrom)) : 0;
    v3.fpsFrom = now; v3.fpsFrames = v3.frames;
    v3.helpDue = true;
  }
  render();
}

// One picture of the scene as it is now.
function render() {
  const t0 = performance.now();
  v3.pendingMove = false;
  const gl = v3.gl, canvas = gl.canvas, cam = v3.cam, mats = v3.mats;
  const W = canvas.clientWidth, H = canvas.clientHeight;
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
  const at = mats.at, eye = mats.eye;
  at[0] = cam.x; at[1] = ty; at[2] = -cam.z;
  eye[0] = at[0] - cam.dist * Math.cos(cam.pitch) * Math.sin(cam.yaw);
  eye[1] = at[1] + cam.dist * Math.sin(cam.pitch);
  eye[2] = at[2] + cam.dist * Math.cos(cam.pitch) * Math.cos(cam.yaw);
  M.mul(mats.mvp, M.perspective(mats.proj, 0.9, W / Math.max(H, 1), Math.max(0.5, cam.dist / 200),
                                cam.dist * 8 + 4000),
        M.lookAt(mats.view, eye, at));
  gl.uniformMatrix4fv(v3.loc.mvp, false, mats.mvp);
  gl.uniform1i(v3.loc.mode, 0);
  if (v3.ground) { gl.bindVertexArray(v3.ground.vao); gl.drawElements(gl.TRIANGLES, v3.ground.count, gl.UNSIGNED_INT, 0); }
  if (v3.bridges) { gl.bindVertexArray(v3.bridges.vao); gl.drawElements(gl.TRIANGLES, v3.bridges.count, gl.UNSIGNED_INT, 0); }
  uploadVehicles(eye);
  const vi = v3.instances;
  // Vehicles at their size up close, larger when far so a marker stays a few pixels.
  gl.uniform1f(v3.loc.scale, Math.max(1, cam.dist / 250));
  if (vi.nearCount) {
    gl.uniform1i(v3.loc.mode, 1);
    gl.bindVertexArray(v3.noAttributes);
    drawShapes(v3.wholeBuffer, vi.wholeCount, v3.shapeVerts);
    drawShapes(v3.hullBuffer, vi.nearCount - vi.wholeCount, v3.hullVerts);
    gl.bindBufferRange(gl.UNIFORM_BUFFER, 1, v3.wholeBuffer.buffer, 0, v3.blockBytes);
  }
  // The rest as one point each (a shape of 72 vertices each costs a CPU rasteriser too much at
  // thousands).
  if (vi.farCount) {
    gl.uniform1i(v3.loc.mode, 2);
    gl.uniform1f(v3.loc.pointPx, 5);
    gl.bindVertexArray(v3.points);
    gl.drawArrays(gl.POINTS, 0, vi.farCount);
  }
  gl.bindVertexArray(null);
  if (v3.cost.finish) gl.finish();
  const d = v3.drawn, w = v3.win;
  d.posts = w.nx * w.nz; d.step = w.step; d.solids = w.solids.length; d.triangles = v3.groundTriangles;
  d.vehicles = vi.shown; d.shapes = vi.nearCount; d.whole = vi.wholeCount; d.points = vi.farCount; d.thinned = vi.thinned;
  d.wholeWithinM = vi.wholeM; d.shapesWithinM = vi.nearM; d.thinnedBeyondM = vi.thinM; d.pixels = PW * PH;
  if (v3.helpDue || v3.helpWindow !== v3.windows) {
    v3.helpDue = false; v3.helpWindow = v3.windows;
    $("help3d").textContent = `3D: ${v3.fps} fps, ${w.nx}×${w.nz} posts every ` +
      `${w.step} m, ${w.solids.length} bridge solids, ${vi.shown} vehicles` +
      (cam.follow ? `, following ${cam.follow}` : "") + (v3.error ? ` (${v3.error})` : "");
  }
  const t1 = performance.now();
  ++v3.cost.frames; v3.cost.ms += t1 - t0;
  noteSlow("dt:draw3d", t0, t1);
}
// The picture as it is now, drawn and read in one task (the canvas keeps no drawing buffer once
// shown): {width, height, rgba} with the top row first. For tests and a saved picture.
v3.snapshot = () => {
  if (!v3.on) return null;
  render();
  const gl = v3.gl, w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
  const up = new Uint8Array(w * h * 4), rgba = new Uint8Array(w * h * 4);
  gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, up);
  for (let y = 0; y < h; ++y) rgba.set(up.subarray((h - 1 - y) * w * 4, (h - y) * w * 4), y * w * 4);
  return { width: w, height: h, rgba };
};

function show(on) {
  if (on && !v3.gl && !setUp()) { $("help3d").textContent = v3.error; }
  v3.on = on && !!v3.gl;
  v3.drawnKey.fill(NaN);  // drawn at once
  v3.vehiclesAt = -1;  // the table's moves were not followed while hidden
  // The map is hidden, not only covered, while the 3D view shows (no layer of it composited),
  // and drawn again when it shows.
  $("mapbox").classList.toggle("three", v3.on);
  if (!v3.on) frame.dirty = true;
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
