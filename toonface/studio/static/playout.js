// stream/playout.py's Playout in the page: the jitter buffer (a delay that rises at once and
// settles slowly to what the recent frames needed), linear concealment with its slope fading and
// the ease to neutral after a long loss, and the speed limit while concealing or catching up.
// The same constants and steps as the Python's ("hold" and "linear"; the recording of what was
// shown is the Python's alone); tests/stream/test_stream_js.py holds the two together.
"use strict";
(() => {
  const MOTORS = 21, SPEED_DECAY = 0.995;

  function percentile(values, q) {
    // numpy's default (linear between the closest ranks)
    const sorted = [...values].sort((a, b) => a - b), rank = (q / 100) * (sorted.length - 1);
    const lo = Math.floor(rank), hi = Math.min(lo + 1, sorted.length - 1);
    return sorted[lo] + (sorted[hi] - sorted[lo]) * (rank - lo);
  }

  const clip = (x, lo, hi) => Math.min(Math.max(x, lo), hi);

  class Playout {
    // `neutral` (21 values); `declared`: the face's own parameters' neutrals, by code
    constructor(neutral, {method = "linear", margin = 0.004, minDelay = 0.0, maxDelay = 0.5, window = 2.0,
      settle = 2.0, maxJump = 0.05, fade = 0.06, easeAfter = 0.3, easeSeconds = 0.5, declared = {}} = {}) {
      if (!["hold", "linear"].includes(method)) throw new Error(`concealment must be hold or linear, got ${method}`);
      Object.assign(this, {method, margin, minDelay, maxDelay, window, settle, maxJump, fade, easeAfter, easeSeconds});
      this.neutral = neutral.slice(0, MOTORS);
      this.declared = declared;
      this.codes = [];
      this.stats = {live: 0, concealed: 0, recovering: 0, waiting: 0};
      this.delay = null;
      this.needed = 0.0;
      this.position = 0.0;
      this.rate = 60.0;
      this.frames = new Map();
      this.anchor = null;  // [frame index, its capture time]
      this.transit = [];  // [arrival, seconds after capture]
      this.output = null;
      this.lastNow = null;
      this.concealedAt = new Map();
      this.behind = false;
      this.first = Number.MAX_SAFE_INTEGER;
      this.index = 0;
      this.speed = new Array(this.neutral.length).fill(0);
      this.newest = [-1, 0.0];
      this.run = 0;
    }

    add(f) {
      // a packet's frames (stream_reader.js's, arrival on the caller's clock)
      this.rate = f.rate;
      if (f.codes.join(" ") !== this.codes.join(" ")) this.carry(f.codes);
      const count = f.values.length;
      const restarted = this.anchor ? f.run !== this.run || f.first < this.anchor[0] - 5 * this.rate : false;
      this.run = f.run;
      if (restarted) {
        this.newest = [-1, 0.0];
        this.frames.clear();
        this.speed.fill(0);
        this.concealedAt.clear();
        this.transit = [];
        this.anchor = null; this.delay = null; this.first = f.first;
      }
      if (this.anchor === null) this.index = f.first;
      if (this.anchor === null || f.first > this.anchor[0]) this.anchor = [f.first, f.time];
      this.first = Math.min(this.first, f.first);
      if (f.first + count - 1 > this.newest[0]) this.newest = [f.first + count - 1, f.arrival];
      for (let i = 0; i < count; i++) {
        const index = f.first + i, captured = f.time + i / f.rate;
        if (i >= f.filled) this.transit.push([f.arrival, f.arrival - captured]);
        this.noteSpeed(index, f.values[i]);
        if (this.concealedAt.has(index)) this.concealedAt.delete(index);  // too late to show
        else this.frames.set(index, f.values[i]);
      }
      while (this.transit.length && this.transit[0][0] < f.arrival - this.window) this.transit.shift();
      if (this.transit.length) {
        const transit = this.transit.map(([, d]) => d), fastest = Math.min(...transit);
        const spread = percentile(transit, 95) - fastest + this.margin;
        this.needed = fastest + Math.min(Math.max(spread, this.minDelay), this.maxDelay);
        if (this.delay === null || this.needed > this.delay) this.delay = this.needed;
      }
      this.forget();
    }

    carry(codes) {
      const rest = (c) => (c in this.declared ? this.declared[c] : (toonWire.EXTRA_REST[c] ?? 0.5));
      this.codes = codes.slice();
      this.neutral = [...this.neutral.slice(0, MOTORS), ...codes.map(rest)];
      this.speed = new Array(this.neutral.length).fill(0);
      this.frames.clear();
      this.concealedAt.clear();
      this.output = null;
    }

    noteSpeed(index, values) {
      for (let c = 0; c < this.speed.length; c++) this.speed[c] *= SPEED_DECAY;
      for (const other of [this.frames.get(index - 1), this.frames.get(index + 1)]) {
        if (other) for (let c = 0; c < this.speed.length; c++) this.speed[c] = Math.max(this.speed[c], Math.abs(values[c] - other[c]));
      }
    }

    latency(offset = 0) {
      // seconds from capture to showing where this clock less the sender's is OFFSET seconds (0: the
      // same clock; the room server tells it, toonface/room/clocks.py); null where that leaves over 10 s
      if (this.delay === null) return null;
      const wrap = 2 ** 32 / 1e3, shown = ((((this.delay - offset + wrap / 2) % wrap) + wrap) % wrap) - wrap / 2;
      return Math.abs(shown) < 10.0 ? shown : null;
    }

    valuesAt(now) {
      // [the values at `now` (the stream's columns), the state: live, concealed, recovering or waiting]
      if (this.anchor === null || this.delay === null) { this.stats.waiting++; return [this.neutral.slice(), "waiting"]; }
      const elapsed = this.lastNow === null ? 0.0 : Math.max(now - this.lastNow, 0.0);
      if (this.delay !== null && this.needed < this.delay) {  // the delay settles toward what is needed
        this.delay = Math.max(this.needed, this.delay - (this.delay - this.needed) * Math.min(elapsed / this.settle, 1.0));
      }
      this.lastNow = now;
      const position = this.anchor[0] + (now - this.delay - this.anchor[1]) * this.rate;
      this.position = position;
      const index = this.index = Math.floor(position);
      if (index < this.first) { this.stats.waiting++; return [(this.frames.get(this.first) || this.neutral).slice(), "waiting"]; }
      const stream = this.streamAt(index, position - index);
      let state, value;
      if (stream !== null && !this.behind) { state = "live"; value = stream; }
      else {
        const target = stream !== null ? stream : this.conceal(index, position);
        value = this.limited(target, elapsed);
        const caughtUp = stream !== null && Math.max(...value.map((v, c) => Math.abs(v - stream[c]))) < 1e-6;
        this.behind = !caughtUp;
        state = caughtUp ? "live" : (stream !== null ? "recovering" : "concealed");
        if (stream === null) {
          if (!this.concealedAt.has(index)) this.concealedAt.set(index, value);
          if (this.concealedAt.size > 4 * this.rate) this.forget();
        }
      }
      this.output = value;
      this.stats[state]++;
      return [value.slice(), state];
    }

    streamAt(index, fraction) {
      const here = this.frames.get(index);
      if (here === undefined) return null;
      const after = this.frames.get(index + 1);
      return after === undefined ? here : here.map((v, c) => v + (after[c] - v) * fraction);
    }

    conceal(index, position) {
      const known = [...this.frames.keys()].filter((k) => k < index).sort((a, b) => a - b).slice(-6);
      if (!known.length) return this.output !== null ? this.output : this.neutral.slice();
      const last = known[known.length - 1], gap = (position - last) / this.rate;
      const values = known.map((k) => this.frames.get(k)), times = known.map((k) => k / this.rate);
      let guess;
      if (this.method === "hold" || known.length < 2) guess = values[values.length - 1].slice();
      else {  // the line through the last three frames (least squares), its slope fading
        const t = times.slice(-3).map((x) => x - times[times.length - 1]), v = values.slice(-3);
        const mt = t.reduce((s, x) => s + x, 0) / t.length, st = t.reduce((s, x) => s + (x - mt) ** 2, 0);
        guess = v[0].map((_, c) => {
          const mv = v.reduce((s, row) => s + row[c], 0) / v.length;
          const slope = t.reduce((s, x, k) => s + (x - mt) * (v[k][c] - mv), 0) / st;
          return mv - slope * mt + slope * this.fade * (1 - Math.exp(-gap / this.fade));
        });
      }
      const ease = clip((gap - this.easeAfter) / this.easeSeconds, 0.0, 1.0);
      return guess.map((g, c) => clip(g + (this.neutral[c] - g) * ease, 0.0, 1.0));
    }

    limited(target, elapsed) {
      if (this.output === null) return target;
      const frames = Math.max(elapsed * this.rate, 1e-9);
      return target.map((x, c) => {
        const step = Math.max(this.speed[c], this.maxJump) * frames;
        return clip(this.output[c] + clip(x - this.output[c], -step, step), 0.0, 1.0);
      });
    }

    forget() {
      const behind = this.index - Math.trunc(2 * this.rate), ahead = this.index + Math.trunc(10 * this.rate);
      for (const k of [...this.frames.keys()]) if (!(behind <= k && k <= ahead)) this.frames.delete(k);
      for (const k of [...this.concealedAt.keys()]) if (k < behind) this.concealedAt.delete(k);
    }
  }

  window.toonPlayout = {Playout};
})();
