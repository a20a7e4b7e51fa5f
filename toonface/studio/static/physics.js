// A face's physics in the page: the drivers of toon/physics.py as the web rig carries them (the
// matrix A of the augmented state, the targets, outputs and kicks), integrated exactly between
// frames with a matrix exponential as the Python does, and run on live frames as
// player/motion.py's SecondaryMotion runs them (one rule: the golden test holds the two together).
"use strict";
(() => {
  const GAP = 1 / 30;  // player/motion.py: live frames further apart are a pause

  const dot = (row, x) => row.reduce((s, a, k) => s + a * x[k], 0);
  const times = (a, b) => a.map((row) => b[0].map((_, j) => row.reduce((s, x, k) => s + x * b[k][j], 0)));

  function expm(a) {
    // e^a for a small square matrix: scaled until small, Taylor to 20 terms, squared back
    const n = a.length, norm = Math.max(...a.map((row) => row.reduce((s, x) => s + Math.abs(x), 0)));
    const s = Math.max(0, Math.ceil(Math.log2(norm / 0.25)));
    const scaled = a.map((row) => row.map((x) => x / 2 ** s));
    let sum = scaled.map((row, i) => row.map((x, j) => x + (i === j ? 1 : 0)));
    let term = scaled;
    for (let k = 2; k <= 20; k++) {
      term = times(term, scaled).map((row) => row.map((x) => x / k));
      sum = sum.map((row, i) => row.map((x, j) => x + term[i][j]));
    }
    for (let k = 0; k < s; k++) sum = times(sum, sum);
    return sum;
  }

  class Physics {
    // the drivers (`p`: a web rig's "physics") and their state, as toon/physics.py's Physics
    constructor(p) {
      this.p = p;
      this.n = p.frequencies.length;
      this.m = p.used.length;
      this.cache = new Map();
      this.reset();
    }

    reset() { this.time = null; this.row = null; this.state = null; }

    advance(t, row) {
      this.state = this.at(t, row);
      this.time = t;
      this.row = this.p.used.map((c) => row[c]);
    }

    moving(tolerance = 1e-3) {
      if (this.time === null) return false;
      const {n, m} = this, x = this.state.slice(0, 2 * n), xw = this.state.slice(0, 2 * n + 2 * m);
      return this.p.target.some((row, k) => Math.abs(x[2 * k] - dot(row, xw)) > tolerance
        || Math.abs(x[2 * k + 1]) / (2 * Math.PI * this.p.frequencies[k]) > tolerance);
    }

    settle() {
      if (this.time === null) return;
      const {n, m} = this, w = this.state.slice(2 * n, 2 * n + 2 * m), x = new Array(2 * n).fill(0);
      for (let k = 0; k < n; k++) x[2 * k] = dot(this.p.target[k], [...x, ...w]);
      this.state = [...x, ...this.state.slice(2 * n)];
    }

    outputs(t, row) {
      // how far each moved column is displaced at t: [[column, amount], ...]
      const x = this.at(t, row);
      return this.p.outputs.map(([column, gain], k) => [column, gain * dot(this.p.output[k], x)]);
    }

    at(t, row) {
      const {n, m} = this, p = this.p;
      const values = p.used.map((c) => row[c] - p.rests[c]);
      if (this.time === null) {  // the first row: every spring at its target, still
        const w = [...values, ...new Array(m).fill(0)], x = new Array(2 * n).fill(0);
        for (let k = 0; k < n; k++) x[2 * k] = dot(p.target[k], [...x, ...w]);
        return [...x, ...w, ...new Array(m).fill(0)];
      }
      const h = t - this.time;
      if (h < -1e-9) throw new Error(`physics goes forward: ${t} s after ${this.time} s`);
      const speeds = this.state.slice(2 * n + m, 2 * n + 2 * m);
      if (h <= 0) return [...this.state.slice(0, 2 * n), ...values, ...speeds, ...new Array(m).fill(0)];
      const last = this.row.map((v, i) => v - p.rests[p.used[i]]);
      const slope = values.map((v, i) => (v - last[i]) / h);
      const x = this.state.slice(0, 2 * n).map((v, i) => v + dot(p.kick[i], slope.map((s, j) => s - speeds[j])));
      const start = [...x, ...last, ...slope, ...slope];
      return this.transition(h).map((r) => dot(r, start));
    }

    transition(h) {
      const key = h.toFixed(12);
      let found = this.cache.get(key);
      if (!found) {
        if (this.cache.size > 512) this.cache.clear();
        found = expm(this.p.a.map((row) => row.map((x) => x * h)));
        this.cache.set(key, found);
      }
      return found;
    }
  }

  class Motion {
    // a face's physics over live frames (player/motion.py SecondaryMotion without a track)
    constructor(p) {
      this.physics = p ? new Physics(p) : null;
      this.rests = p ? p.rests : [];
      this.last = null;
      this.held = null;
      this.heldAt = null;
    }

    moving() { return this.physics !== null && this.physics.moving(); }

    frame(t, row) {
      // the full row to draw at t seconds for the frame `row` (one value a code): what the
      // drivers move added to it, within [0, 1]
      if (!this.physics) return row;
      if (this.last !== null && t < this.last - 1e-9) { this.physics.reset(); this.held = null; this.heldAt = null; }
      this.last = t;
      if (this.held !== null && t - this.heldAt > GAP) this.physics.advance(t - GAP, this.held);
      this.physics.advance(t, row);
      this.held = row;
      this.heldAt = t;
      if (!this.physics.moving()) this.physics.settle();
      const out = row.slice(), moved = new Map();
      for (const [column, amount] of this.physics.outputs(t, row)) moved.set(column, (moved.get(column) || 0) + amount);
      for (const [column, amount] of moved) out[column] = Math.min(Math.max(row[column] + amount, 0), 1);
      return out;
    }
  }

  class TrackMotion {
    // a face's physics over a track's samples (SecondaryMotion with a track): `rows` (one a
    // sample, the rig's columns) at `rate`; frames drawn at any rate, or sought in any order, show
    // the same motion at the same instants
    constructor(p, rate, rows) {
      this.physics = p ? new Physics(p) : null;
      this.rate = rate;
      this.rows = rows;
      this.next = 0;
      this.last = null;
    }

    row(t) {
      // the track's row at t seconds, linear between samples, held beyond its ends
      const k = Math.min(Math.max(Math.floor(t * this.rate + 1e-9), 0), this.rows.length - 1);
      if (k >= this.rows.length - 1 || t <= 0) return this.rows[t <= 0 ? 0 : k].slice();
      const share = (t - k / this.rate) * this.rate, a = this.rows[k], b = this.rows[k + 1];
      return a.map((v, c) => v + (b[c] - v) * share);
    }

    frame(t) {
      // the row to draw at t: the track's, with what the drivers move added (within [0, 1])
      const row = this.row(t);
      if (!this.physics) return row;
      if (this.last !== null && t < this.last - 1e-9) { this.physics.reset(); this.next = 0; }
      this.last = t;
      while (this.next < this.rows.length && this.next / this.rate <= t + 1e-9) {
        this.physics.advance(this.next / this.rate, this.rows[this.next]);
        this.next += 1;
      }
      const out = row.slice(), moved = new Map();
      for (const [column, amount] of this.physics.outputs(t, row)) moved.set(column, (moved.get(column) || 0) + amount);
      for (const [column, amount] of moved) out[column] = Math.min(Math.max(row[column] + amount, 0), 1);
      return out;
    }
  }

  window.toonPhysics = {Physics, Motion, TrackMotion, expm};
})();
