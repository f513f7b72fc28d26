// The live view's page: one WebSocket, a snapshot then deltas (docs/view.md "Messages").
"use strict";
const SVG = "http://www.w3.org/2000/svg";
const state = {
  size_x: 1000, size_z: 1000, exercise: null, seq: 0, features: new Map(), processes: [], vehicles: new Map(),
  selected: null, view: null, ws: null, req: 0,
};
// For tests and for the curious: when each feature was first drawn (Date.now()), and the
// sequence of the last message applied.
window.dtView = { state, drawnAt: {}, appliedSeq: 0, snapshotAt: 0, deltas: 0 };

const $ = (id) => document.getElementById(id);
function hue(text) {
  let h = 0;
  for (const c of text) h = (h * 31 + c.charCodeAt(0)) >>> 0;
  return h % 360;
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
  if (!(f.id in window.dtView.drawnAt)) window.dtView.drawnAt[f.id] = Date.now();
  if (state.selected === f.id) { g.classList.add("selected"); showFeature(); }
}
function removeFeature(id) {
  const g = $("features").querySelector(`[data-id="${id}"]`);
  if (g) g.remove();
  state.features.delete(id);
  if (state.selected === id) { state.selected = null; showFeature(); }
}

const vehicleMarks = new Map();  // vehicle ID -> its marker
// One vehicle's marker, replaced in place when it moves (a delta carries only those that did).
// A vehicle arrives as [id, owner, type, x, z, heading, speed, alive] (docs/view.md "Messages").
function vehicleOf([id, owner, type, x, z, heading, speed, alive]) {
  return { id, owner, type, x, z, heading, speed, alive };
}
function drawVehicle(row) {
  const v = vehicleOf(row);
  const layer = $("vehicles");
  const old = vehicleMarks.get(v.id);
  const s = 12;  // metres: a marker, not the vehicle's size
  const g = el("g", { class: "vehicle", "data-id": v.id, "data-alive": v.alive ? 1 : 0,
    transform: `translate(${v.x},${Y(v.z)}) rotate(${-v.heading * 180 / Math.PI})` });
  el("polygon", { points: `${s},0 ${-s * 0.7},${s * 0.6} ${-s * 0.7},${-s * 0.6}`,
                  fill: v.alive ? ownerColour(v.owner) : "#666", stroke: "#000" }, g);
  if (!v.alive) el("path", { d: `M${-s},${-s} L${s},${s} M${-s},${s} L${s},${-s}`,
                             stroke: "#ff3b2b", "stroke-width": 3 }, g);
  if (old) old.replaceWith(g); else layer.appendChild(g);
  vehicleMarks.set(v.id, g);
  state.vehicles.set(v.id, v);
}
function removeVehicle(id) {
  const g = vehicleMarks.get(id);
  if (g) g.remove();
  vehicleMarks.delete(id);
  state.vehicles.delete(id);
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

function select(id) {
  const old = $("features").querySelector(".selected");
  if (old) old.classList.remove("selected");
  state.selected = id;
  const g = id && $("features").querySelector(`[data-id="${id}"]`);
  if (g) g.classList.add("selected");
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

function applyFeatures(list) {
  for (const f of list) { state.features.set(f.id, f); drawFeature(f); }
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
  applyFeatures(s.features);
  $("events").replaceChildren();
  addEvents(s.events);
  state.processes = s.processes;
  drawProcesses();
  $("vehicles").replaceChildren();
  vehicleMarks.clear();
  state.vehicles.clear();
  s.vehicles.forEach(drawVehicle);
  setRelief(s.relief);
  if (s.exercise.commands) setUpOperator(s.exercise.nodes);
  window.dtView.snapshotAt = Date.now();
}
function onDelta(d) {
  if (d.removed) d.removed.forEach(removeFeature);
  if (d.features) applyFeatures(d.features);
  if (d.events) addEvents(d.events);
  if (d.processes) { state.processes = d.processes; drawProcesses(); }
  if (d.vehicles_removed) d.vehicles_removed.forEach(removeVehicle);
  if (d.vehicles) d.vehicles.forEach(drawVehicle);
  if (d.relief !== undefined) setRelief(d.relief);
  window.dtView.deltas++;
}
function onMessage(ev) {
  const m = JSON.parse(ev.data);
  if (m.type === "snapshot") onSnapshot(m);
  else if (m.type === "delta") onDelta(m);
  else if (m.type === "reply") {
    $("op-reply").textContent = `${m.ok ? "ok" : "refused"}: ${m.line || ""} ${m.text}`;
    window.dtView.lastReply = m;
  }
  if (m.seq !== undefined) window.dtView.appliedSeq = m.seq;
  $("stats").textContent = `${state.features.size} features, ${state.vehicles.size} vehicles,` +
    ` message ${window.dtView.appliedSeq}, ${Date.now() - m.t_ms} ms after it was sent`;
}
function connect() {
  const ws = new WebSocket(`ws://${location.host}/ws`);
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
}
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
  if (!tool || !state.exercise || !state.exercise.commands) { select(null); return; }
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
