// The page's vehicles in typed arrays indexed by the slot dt_view gives each (docs/view.md "The
// binary vehicle message"): a move read from a binary message is a few stores, with no object per
// vehicle made or collected, and the drawing reads the arrays directly.
"use strict";
const VEHICLE_MAGIC = 0x31565444;  // "DTV1", little-endian
class VehicleTable {
  constructor() {
    this.cap = 0; this.end = 0; this.size = 0;
    this.slotOf = new Map(); this.ids = [];
    this.owners = []; this.ownerIndex = new Map(); this.types = []; this.typeIndex = new Map();
    this.changed = new Uint32Array(0); this.changedN = 0;  // slots moved since takeChanged()
    this.localNext = 1 << 30;  // slots for rows that name none (feeds without binary messages)
    this.grow(1024);
  }
  grow(need) {
    if (need <= this.cap) return;
    let cap = Math.max(1024, this.cap);
    while (cap < need) cap *= 2;
    const copy = (Type, old) => { const a = new Type(cap); if (old) a.set(old); return a; };
    this.x = copy(Float32Array, this.x); this.z = copy(Float32Array, this.z);
    this.heading = copy(Float32Array, this.heading); this.speed = copy(Float32Array, this.speed);
    this.alive = copy(Uint8Array, this.alive); this.used = copy(Uint8Array, this.used);
    this.owner = copy(Uint16Array, this.owner); this.type = copy(Uint8Array, this.type);
    this.pending = copy(Uint8Array, this.pending);
    this.changed = copy(Uint32Array, this.changed);
    this.cap = cap;
  }
  index(list, map, name) {
    let i = map.get(name);
    if (i === undefined) { i = list.length; list.push(name); map.set(name, i); }
    return i;
  }
  mark(slot) {
    if (this.pending[slot]) return;
    this.pending[slot] = 1;
    this.changed[this.changedN++] = slot;
  }
  // The slots moved since the last call (each once), for the 3D view's instance buffer.
  takeChanged(fn) {
    for (let i = 0; i < this.changedN; ++i) { const s = this.changed[i]; this.pending[s] = 0; fn(s); }
    this.changedN = 0;
  }
  clear() {
    for (let s = 0; s < this.end; ++s) if (this.used[s]) { this.used[s] = 0; this.mark(s); }
    this.slotOf.clear(); this.ids = []; this.size = 0; this.end = 0;
  }
  // A row, [id, owner, type, x, z, heading, speed, alive, slot].
  setRow(row) {
    const [id, owner, type, x, z, heading, speed, alive] = row;
    let slot = row[8];
    const had = this.slotOf.get(id);
    if (slot === undefined) slot = had !== undefined ? had : this.localNext++ - (1 << 30);
    if (had !== undefined && had !== slot) this.freeSlot(had);
    this.grow(slot + 1);
    // A slot given again: the vehicle that held it is gone (its removal came first).
    if (this.used[slot] && this.ids[slot] !== id) this.freeSlot(slot);
    if (!this.used[slot]) ++this.size;
    this.used[slot] = 1; this.ids[slot] = id; this.slotOf.set(id, slot);
    this.owner[slot] = this.index(this.owners, this.ownerIndex, owner);
    this.type[slot] = this.index(this.types, this.typeIndex, type);
    this.x[slot] = x; this.z[slot] = z; this.heading[slot] = heading; this.speed[slot] = speed;
    this.alive[slot] = alive ? 1 : 0;
    this.end = Math.max(this.end, slot + 1);
    this.mark(slot);
  }
  freeSlot(slot) {
    if (!this.used[slot]) return;
    this.used[slot] = 0; --this.size; this.mark(slot);
    this.slotOf.delete(this.ids[slot]); this.ids[slot] = undefined;
    while (this.end > 0 && !this.used[this.end - 1]) --this.end;
  }
  remove(id) { const s = this.slotOf.get(id); if (s !== undefined) this.freeSlot(s); }
  // A binary vehicle message: returns {seq, t_ms, count}, or null when it is not one.
  applyFrame(buf) {
    if (buf.byteLength < 24) return null;
    const head = new Uint32Array(buf, 0, 6);
    if (head[0] !== VEHICLE_MAGIC) return null;
    const count = head[4];
    if (buf.byteLength !== 24 + 16 * count) return null;
    const u32 = new Uint32Array(buf, 24, count * 4), f32 = new Float32Array(buf, 24, count * 4),
          i16 = new Int16Array(buf, 24, count * 8);
    for (let i = 0; i < count; ++i) {
      const word = u32[i * 4], slot = word & 0x7fffffff;
      if (slot >= this.cap || !this.used[slot]) continue;  // not (or no longer) listed
      this.x[slot] = f32[i * 4 + 1]; this.z[slot] = f32[i * 4 + 2];
      this.heading[slot] = i16[i * 8 + 6] / 10000; this.speed[slot] = i16[i * 8 + 7] / 100;
      this.alive[slot] = word >>> 31 ? 0 : 1;
      this.mark(slot);
    }
    return { seq: head[1], t_ms: new Float64Array(buf, 8, 1)[0], count };
  }
  // For tests and the follow box: a vehicle as its row (made on demand).
  row(slot) {
    return [this.ids[slot], this.owners[this.owner[slot]], this.types[this.type[slot]], this.x[slot],
            this.z[slot], this.heading[slot], this.speed[slot], !!this.alive[slot], slot];
  }
  get(id) { const s = this.slotOf.get(id); return s === undefined ? undefined : this.row(s); }
  has(id) { return this.slotOf.has(id); }
  *values() { for (let s = 0; s < this.end; ++s) if (this.used[s]) yield this.row(s); }
}
