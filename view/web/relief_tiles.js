// The relief as tiles (docs/view.md "The relief"): for what is in view, the tiles of the level
// whose pixel is no wider than the screen's, drawn over the coarser ones until they arrive; a tile
// is asked again only when its version changed.
"use strict";
const relief = { info: null, tiles: new Map(), level: 0, complete: false, completeAt: 0,
                 loaded: 0, groups: [] };
window.dtView.relief = relief;

function reliefVersion(key) {
  const v = relief.info.versions[key];
  return v !== undefined ? v : relief.info.epoch;
}
function reliefSide(level) { return relief.info.side_m / 2 ** level; }
// From the snapshot: the pyramid and every tile's version. The single relief image is not used.
function setReliefTiles(info) {
  relief.info = info;
  $("relief").removeAttribute("href");
  const box = $("relieftiles");
  box.replaceChildren();
  relief.tiles.clear();
  relief.groups = [];
  for (let l = 0; l < info.levels; ++l) {  // finer levels over coarser ones
    const g = document.createElementNS(SVG, "g");
    box.appendChild(g);
    relief.groups.push(g);
  }
  relief.complete = false;
  updateRelief();
}
// A relief_tiles message: the tiles a change touched (or, with a new epoch, all).
function applyReliefTiles(m) {
  if (!relief.info) return;
  if (m.epoch !== relief.info.epoch) { relief.info.epoch = m.epoch; relief.info.versions = {}; }
  Object.assign(relief.info.versions, m.versions);
  updateRelief();
}
function loadTile(key, version) {
  let e = relief.tiles.get(key);
  if (e && e.loading === version) return;
  if (!e) { e = { el: null, version: -1, loading: version }; relief.tiles.set(key, e); }
  e.loading = version;
  const [level, tx, tz] = key.split("/").map(Number);
  const url = `/relief/${key}.png?v=${version}`;
  const img = new Image();
  img.onload = () => {
    if (relief.tiles.get(key) !== e || e.loading !== version) return;  // dropped, or a newer one
    const s = reliefSide(level), el = document.createElementNS(SVG, "image");
    el.setAttribute("href", url);
    el.setAttribute("preserveAspectRatio", "none");
    for (const [k, v] of [["x", tx * s], ["y", state.size_z - (tz + 1) * s], ["width", s],
                          ["height", s]]) el.setAttribute(k, v);
    el.dataset.key = key;
    el.dataset.version = version;
    relief.groups[level].appendChild(el);
    if (e.el) e.el.remove();  // the older picture goes once the newer one is there
    e.el = el; e.version = version; e.loading = null;
    ++relief.loaded;
    updateRelief();
  };
  img.onerror = () => {  // busy or not drawn in time: asked again a little later
    if (relief.tiles.get(key) !== e || e.loading !== version) return;
    e.loading = null;
    setTimeout(updateRelief, 500);
  };
  img.src = url;
}
// The tiles for the view: level 0 always (nothing is ever blank), and the level whose pixel
// matches the screen's over what is in view. Tiles of other levels stay until these are drawn.
function updateRelief() {
  if (!relief.info || !state.view) return;
  const info = relief.info, t = transform();
  const mpp = t.s / (window.devicePixelRatio || 1);
  let level = 0;
  while (level < info.levels - 1 && reliefSide(level) / info.tile_px > mpp) ++level;
  relief.level = level;
  const s = reliefSide(level);
  const nx = Math.max(1, Math.ceil(state.size_x / s - 1e-9));
  const nz = Math.max(1, Math.ceil(state.size_z / s - 1e-9));
  const clamp = (v, n) => Math.min(n - 1, Math.max(0, Math.floor(v / s)));
  const x0 = t.ox, x1 = t.ox + t.W * t.s;
  const z1 = state.size_z - t.oy, z0 = state.size_z - (t.oy + t.H * t.s);
  const need = new Set(["0/0/0"]);
  if (x1 >= 0 && z1 >= 0 && x0 <= state.size_x && z0 <= state.size_z) {
    for (let tz = clamp(z0, nz); tz <= clamp(z1, nz); ++tz) {
      for (let tx = clamp(x0, nx); tx <= clamp(x1, nx); ++tx) need.add(`${level}/${tx}/${tz}`);
    }
  }
  let complete = true;
  for (const key of need) {
    const v = reliefVersion(key), e = relief.tiles.get(key);
    if (!e || e.version !== v) { complete = false; loadTile(key, v); }
  }
  if (complete) {
    for (const [key, e] of relief.tiles) {
      if (need.has(key)) continue;
      if (e.el) e.el.remove();
      relief.tiles.delete(key);
    }
    if (!relief.completeAt) relief.completeAt = Date.now();
  }
  relief.complete = complete;
  relief.need = [...need];
}
window.addEventListener("resize", updateRelief);
