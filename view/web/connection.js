// The page's one WebSocket (docs/view.md "Messages"): a snapshot then deltas, queued as they arrive
// and applied once per animation frame. Loaded last: it starts the page.
"use strict";
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
  // dt_view serves the relief as tiles; a server without them, the one picture /relief.png.
  if (s.relief_tiles) setReliefTiles(s.relief_tiles);
  else setRelief(s.relief);
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
  if (d.relief !== undefined && !relief.info) setRelief(d.relief);
  // The 3D view asks for its terrain window again (the ground or a feature changed).
  if (d.removed || d.features || d.relief !== undefined) ++window.dtView.terrainVersion;
  window.dtView.deltas++;
}
// Messages are queued as they arrive and applied once per animation frame, all of them at once:
// a vehicle moved by several queued deltas is drawn once, at its latest place, and the page's
// work per frame does not grow with the message rate (docs/view.md "Drawing at scale").
// Each message's arrival (Date.now()) is kept beside it: the lag splits into the time before the
// page's thread received it (the sender, the network, the browser) and the time it waited here.
const inbox = [], arrivedAt = [];
let processesDirty = false;
function onMessage(ev) {
  inbox.push(ev.data);
  arrivedAt.push(Date.now());
  window.dtView.wsBytes += typeof ev.data === "string" ? ev.data.length : ev.data.byteLength;
}
// The binary vehicle message: the moves of vehicles the page knows, by slot.
function applyVehicleFrame(buf, arrived) {
  const h = state.vehicles.applyFrame(buf);
  if (!h) return;
  frame.dirty = true;
  window.dtView.deltas++;
  window.dtView.appliedSeq = Math.max(window.dtView.appliedSeq, h.seq);
  noteLag(h.t_ms, arrived);
}
function noteLag(t_ms, arrived) {
  const d = window.dtView, now = Date.now(), lag = now - t_ms;
  d.lagMs = lag;
  d.maxLagMs = Math.max(d.maxLagMs || 0, lag);
  if (arrived === undefined) return;
  d.maxTransitMs = Math.max(d.maxTransitMs || 0, arrived - t_ms);
  d.maxQueuedMs = Math.max(d.maxQueuedMs || 0, now - arrived);
}
function applyMessage(m, arrived) {
  if (m.type === "snapshot") onSnapshot(m);
  else if (m.type === "delta") onDelta(m);
  else if (m.type === "relief_tiles") applyReliefTiles(m);
  else if (m.type === "reply") {
    $("op-reply").textContent = `${m.ok ? "ok" : "refused"}: ${m.line || ""} ${m.text}`;
    window.dtView.lastReply = m;
  }
  if (m.seq !== undefined) window.dtView.appliedSeq = m.seq;
  if (m.t_ms !== undefined) noteLag(m.t_ms, arrived);
}
function tick(now) {
  const cost = window.dtView.cost;
  const t0 = performance.now(), messages = inbox.length;
  if (messages) {
    const batch = inbox.splice(0, inbox.length), arrived = arrivedAt.splice(0, arrivedAt.length);
    for (let i = 0; i < batch.length; ++i) {
      if (typeof batch[i] === "string") applyMessage(JSON.parse(batch[i]), arrived[i]);
      else applyVehicleFrame(batch[i], arrived[i]);
    }
    cost.messages += batch.length;
    if (processesDirty) { drawProcesses(); processesDirty = false; }
    $("stats").textContent = `${state.features.size} features, ${state.vehicles.size} vehicles,` +
      ` message ${window.dtView.appliedSeq}, ${window.dtView.lagMs} ms after it was sent`;
  }
  // A resting view whose feature cache is older than the view is drawn once more, and a frame
  // is drawn while the cache's render goes on (a slice each).
  const cacheBehind = featuresOnCanvas() && (featureCache.job !== null ||
    featureCache.version !== frame.featuresVersion ||
    featureCache.tView !== null && now - frame.viewChangedAt > 150 &&
    featureCache.renderedAt < frame.viewChangedAt);
  const t1 = performance.now();
  // Under the 3D view the map is not drawn: it is drawn when it shows again.
  const under3d = window.dtView3d && window.dtView3d.on;
  if ((frame.dirty || cacheBehind) && state.view && !under3d) {
    frame.dirty = false;
    drawFrame(now);
    ++cost.draws;
  }
  const t2 = performance.now();
  noteSlow("dt:apply", t0, t1, messages);
  noteSlow("dt:draw", t1, t2);
  cost.applyMs += t1 - t0;
  cost.drawMs += t2 - t1;
  ++window.dtView.frames;
  requestAnimationFrame(tick);
}
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

requestAnimationFrame(tick);
connect();
