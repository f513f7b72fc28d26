// The panels beside and under the map: processes, the selected feature, the event log and the
// operator's actions.
"use strict";
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
