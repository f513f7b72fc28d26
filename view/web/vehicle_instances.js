// The 3D view's vehicles as instances: per slot of the page's vehicle table its place on the
// ground, heading, owner's colour and dead flag; each drawn frame the nearest as shapes, the rest
// as points, the far ones thinned (docs/view.md "The 3D view"). Shapes come in two levels: the
// nearest whole (hull, turret, gun), the next the hull alone, a third of the vertices.
"use strict";
// An instance's floats: x, y (the ground's height under it), z, heading; r, g, b, dead (1 or 0).
const INSTANCE_FLOATS = 8;
const DISTANCE_BUCKETS = 1024;  // the nearest found from a histogram of distances, not a sort
const THIN_MAX = 64;            // the farthest points thinned to one in this many at most
class VehicleInstances {
  // wholeMax: whole shapes at most; nearMax: shapes at most (the rest hulls); pointsAll: points
  // drawn all up to this many, thinned beyond it.
  constructor(wholeMax, nearMax, pointsAll) {
    this.pointsAll = pointsAll;
    this.cap = 0;
    this.hist = new Uint32Array(DISTANCE_BUCKETS);
    this.setNearMax(wholeMax, nearMax);
    this.wholeCount = 0; this.nearCount = 0; this.farCount = 0; this.thinned = 0; this.shown = 0;
    this.wholeM = Infinity; this.nearM = Infinity; this.thinM = Infinity;
  }
  // Arrays for a table of `cap` slots, every slot hidden; allocates only when the table grew.
  reset(cap) {
    if (cap !== this.cap) {
      this.cap = cap;
      this.slots = new Float32Array(cap * INSTANCE_FLOATS);
      this.isShown = new Uint8Array(cap);
      this.dist = new Float32Array(cap);
      this.far = new Float32Array(cap * INSTANCE_FLOATS);
    }
    this.isShown.fill(0);
    this.shown = 0;
  }
  setNearMax(whole, near) {
    this.wholeMax = Math.min(whole, near); this.nearMax = near;
    this.whole = new Float32Array(Math.max(1, this.wholeMax) * INSTANCE_FLOATS);
    this.hulls = new Float32Array(Math.max(1, near - this.wholeMax) * INSTANCE_FLOATS);
  }
  // Slot s of table tb written again; y is the ground's height under it, null when it is not on
  // the terrain window (or the slot holds no vehicle). Returns whether it shows or showed.
  set(tb, s, y, rgb) {
    const was = this.isShown[s], now = y === null ? 0 : 1;
    this.isShown[s] = now;
    this.shown += now - was;
    if (!now) return was === 1;
    const d = this.slots, o = s * INSTANCE_FLOATS;
    d[o] = tb.x[s]; d[o + 1] = y; d[o + 2] = tb.z[s]; d[o + 3] = tb.heading[s];
    d[o + 4] = rgb[0] / 255; d[o + 5] = rgb[1] / 255; d[o + 6] = rgb[2] / 255;
    d[o + 7] = tb.alive[s] ? 0 : 1;
    return true;
  }
  // The radius holding at most m of the shown vehicles: the lower edge of the first bucket of the
  // histogram that would pass m (those nearer are all in), Infinity when all are fewer.
  radiusFor(m, bucketM) {
    let sum = 0;
    for (let b = 0; b < DISTANCE_BUCKETS; ++b) {
      if (sum + this.hist[b] > m) return b * bucketM;
      sum += this.hist[b];
    }
    return Infinity;
  }
  // The frame's instances for an eye at (ex, ey, ez) in GL's frame (z is the terrain's -z), in
  // place: `whole` the whole shapes (the nearest, at most wholeMax, every one nearer than wholeM),
  // `hulls` the next (together at most nearMax, nearer than nearM), `far` the points. Beyond thinM (the radius of pointsAll / 2 vehicles, when there are more than
  // pointsAll) one point in 4^k is kept within its k-th doubling, by slot, so a kept vehicle stays
  // kept as the camera moves a little: the points per pixel of a perspective view's far ground
  // stay about even, and their count bounded.
  select(end, ex, ey, ez) {
    const d = this.slots, shown = this.isShown, dist = this.dist, F = INSTANCE_FLOATS;
    let dmax = 0;
    for (let s = 0; s < end; ++s) {
      if (!shown[s]) continue;
      const o = s * F, dx = d[o] - ex, dy = d[o + 1] - ey, dz = -d[o + 2] - ez;
      const r = Math.sqrt(dx * dx + dy * dy + dz * dz);
      dist[s] = r;
      if (r > dmax) dmax = r;
    }
    this.wholeM = Infinity; this.nearM = Infinity; this.thinM = Infinity;
    if (this.shown > this.wholeMax) {
      const perM = (DISTANCE_BUCKETS - 1) / Math.max(dmax, 1e-3);
      this.hist.fill(0);
      for (let s = 0; s < end; ++s) if (shown[s]) ++this.hist[Math.floor(dist[s] * perM)];
      this.wholeM = this.radiusFor(this.wholeMax, 1 / perM);
      this.nearM = this.radiusFor(this.nearMax, 1 / perM);
      if (this.shown > this.pointsAll) this.thinM = this.radiusFor(this.pointsAll / 2, 1 / perM);
    }
    const whole = this.whole, hulls = this.hulls, far = this.far, thinM = this.thinM;
    const hullMax = this.nearMax - this.wholeMax;
    let w = 0, h = 0, f = 0, thinned = 0;
    for (let s = 0; s < end; ++s) {
      if (!shown[s]) continue;
      const r = dist[s];
      let to, at;
      if (r < this.wholeM && w < this.wholeMax) {
        to = whole; at = w++;
      } else if (r < this.nearM && h < hullMax) {
        to = hulls; at = h++;
      } else {
        if (r > thinM) {
          const every = Math.min(THIN_MAX, 4 ** Math.ceil(Math.log2(r / thinM)));
          if (s % every !== 0) { ++thinned; continue; }
        }
        to = far; at = f++;
      }
      const o = s * F, t = at * F;
      for (let i = 0; i < F; ++i) to[t + i] = d[o + i];
    }
    this.wholeCount = w; this.nearCount = w + h; this.farCount = f; this.thinned = thinned;
  }
}
