// stream/reader.py's StreamReader in the page: datagrams in, checked, de-duplicated, re-ordered and
// decoded frames out, acknowledgements and keyframe requests back (stream.js holds the format).
"use strict";
(() => {
  const W = window.toonWire, C = W.constants, {behind, mod} = W;

  class FrameStore {
    // the last KEEP frames by index, each with its depth in its chain (stream/packets.py)
    constructor() { this.rows = new Map(); this.order = []; }

    put(index, levels, depth) {
      if (!this.rows.has(index)) this.order.push(index);
      this.rows.set(index, [levels, Math.min(depth, 2)]);
      while (this.order.length > C.KEEP) this.rows.delete(this.order.shift());
    }

    has(index) { return this.rows.has(index); }
    depth(index) { return this.rows.get(index)[1]; }
    row(index) { return this.rows.get(index)[0]; }

    history(reference) {
      if (!this.rows.has(reference)) return null;
      const wanted = [];
      for (let k = this.rows.get(reference)[1]; k >= 0; k--) wanted.push(mod(reference - k));
      if (wanted.some((w) => !this.rows.has(w))) return null;
      return wanted.map((w) => this.rows.get(w)[0]);
    }
  }

  const reference = (h) => mod(h.first - h.back);

  function after(anchor, h) {
    // the anchor once header h is read (stream/framing.py Anchor.after)
    if (h.flags & C.LONG) {
      return {sequence: h.sequence, first: h.first, longFrame: h.first, time: h.time, steps: h.steps, rate: h.rate, usual: h.usual};
    }
    return {...anchor, sequence: h.sequence, first: h.first};
  }

  function unwrap(raw, mark) {
    if (!mark) return [raw, raw];
    const step = mod(raw - mark[0]);
    return [raw, mark[1] + (step >= C.WRAP / 2 ? step - C.WRAP : step)];
  }

  class StreamReader {
    // see stream/reader.py; times are seconds on the page's clock; `key`: toonWire.streamKey's
    constructor(key = null, maxWaiting = 16, idleReset = 2.0) {
      this.key = key;
      this.maxWaiting = maxWaiting;
      this.idleReset = idleReset;
      this.dropped = {};
      this.packets = 0; this.bytes = 0; this.lost = 0;
      this.wantKeyframe = false;
      this.stream = 0;
      this.codes = [];
      this.unnamed = false;
      this.models = new Map();
      this.newest = null; this.firstSequence = 0; this.run = -1; this.runs = []; this.seen = 0n;
      this.lastValid = -Infinity; this.anchor = null; this.lossAt = -Infinity; this.ackedAt = -Infinity;
      this.now = -Infinity; this.named = null; this.held = new FrameStore(); this.ack = null; this.ackDue = false;
      this.waiting = new Map(); this.frameMark = null; this.timeMark = null;
    }

    drop(reason) { this.dropped[reason] = (this.dropped[reason] || 0) + 1; }

    read(datagram, arrival) {
      // the frames this datagram completes: [{first, time, rate, values, arrival, codes, run, filled}]
      let anchor = this.anchor;
      if (anchor && arrival - this.lastValid > Math.min(C.ANCHOR_SECONDS, C.ANCHOR_FRAMES / anchor.rate)) anchor = null;
      let header, body;
      try {
        [header, body] = W.openPacket(datagram, anchor, this.key);
      } catch (error) {
        if (!(error instanceof W.WireError)) throw error;
        this.drop(error.reason);
        if (error.reason === "unanchored") this.wantKeyframe = true;
        return [];
      }
      if (header.flags & (C.KEY_REQUEST | C.ACK)) { this.drop("request"); return []; }
      const lost = this.lost;
      if (!this.fresh(header.sequence, arrival)) { this.drop("replay"); return []; }
      this.now = arrival;
      const seen = this.named, last = mod(header.first + Math.max(header.count, 1) - 1);
      if (seen === null || behind(seen, last)) this.named = last;
      if (this.lost > lost) this.lossAt = arrival;
      this.packets++;
      this.bytes += datagram.length;
      this.stream = header.stream;
      this.lastValid = arrival;
      if (!this.anchor || !anchor || !behind(header.sequence, this.anchor.sequence)) {
        this.anchor = after(this.anchor || {sequence: 0, first: 0, longFrame: 0, time: 0, steps: 1, rate: 1, usual: 0}, header);
      }
      if (!(header.flags & C.KEYFRAME) && this.held.history(reference(header)) === null) {
        this.lossAt = arrival;
        this.wait(header, body, arrival, seen);
        this.want(arrival);
        return [];
      }
      let out = this.decode(header, body, arrival, seen);
      let progress = true;
      while (progress && this.waiting.size) {
        progress = false;
        for (const [first, [h, b, a, s]] of [...this.waiting]) {
          if (this.held.history(reference(h)) !== null) {
            this.waiting.delete(first);
            out = out.concat(this.decode(h, b, a, s));
            progress = true;
          }
        }
      }
      for (const [first, [h]] of [...this.waiting]) {
        let all = true;
        for (let k = 0; k < h.count; k++) if (!this.held.has(mod(first + k))) all = false;
        if (all) { this.waiting.delete(first); this.drop("obsolete"); }
      }
      this.want(arrival);
      return out;
    }

    takeAck() {
      // the acknowledgement to send now (bytes), or null
      const lossy = this.now - this.lossAt < C.LOSS_SECONDS;
      if (this.ack === null || !this.ackDue || (!lossy && this.now - this.ackedAt < C.ACK_INTERVAL)) return null;
      this.ackDue = false;
      this.ackedAt = this.now;
      let held = 0;
      for (let i = 0; i < C.ACK_BITS; i++) if (this.held.has(mod(this.ack - 1 - i))) held += 2 ** i;
      return W.sealReply(C.ACK | (lossy ? C.PARAMS : 0), this.stream, this.ack, held, this.key);
    }

    keyframeRequest() { return W.sealReply(C.KEY_REQUEST, this.stream, 0, 0, this.key); }

    want(now) {
      this.wantKeyframe = this.unnamed || [...this.waiting].some(([first, [, , a]]) =>
        now - a >= C.KEY_WAIT && (this.ack === null || !behind(first, this.ack)));
    }

    wait(header, body, arrival, seen) {
      this.waiting.set(header.first, [header, body, arrival, seen]);
      if (this.waiting.size > this.maxWaiting) {
        let worst = null;
        for (const k of this.waiting.keys()) if (worst === null || mod(header.first - k) > mod(header.first - worst)) worst = k;
        this.waiting.delete(worst);
        this.drop("overflow");
      }
    }

    fresh(sequence, arrival) {
      if (this.newest === null || arrival - this.lastValid > this.idleReset) {
        const runs = this.runs.concat(this.newest !== null ? [[this.firstSequence, this.newest]] : []);
        if (runs.some(([first, newest]) => mod(sequence - first) <= mod(newest - first))) return false;
        this.runs = runs.slice(-C.SESSIONS_KEPT);
        this.newest = sequence; this.seen = 1n; this.firstSequence = sequence;
        this.run++;
        this.held = new FrameStore(); this.ack = null; this.waiting = new Map();
        this.named = null;
        return true;
      }
      const ahead = mod(sequence - this.newest);
      if (ahead > 0 && ahead < C.WRAP / 2) {
        this.lost += Math.min(ahead, C.REPLAY_WINDOW) - 1;
        this.seen = ((this.seen << BigInt(Math.min(ahead, 128))) | 1n) & ((1n << BigInt(C.REPLAY_WINDOW)) - 1n);
        this.newest = sequence;
        return true;
      }
      const back = mod(this.newest - sequence);
      if (back >= C.REPLAY_WINDOW || (this.seen >> BigInt(back)) & 1n) return false;
      this.seen |= 1n << BigInt(back);
      this.lost = Math.max(0, this.lost - 1);
      return true;
    }

    decode(header, body, arrival, seen) {
      let models = this.models.get(header.steps);
      if (!models) {
        if (this.models.size >= 4) this.models.clear();
        models = new W.Models(header.steps);
        this.models.set(header.steps, models);
      }
      const keyframe = Boolean(header.flags & C.KEYFRAME), params = Boolean(header.flags & C.PARAMS);
      let section = null;
      try {
        [section, body] = this.unpackParams(header, body);
      } catch (error) {
        if (!(error instanceof W.WireError)) throw error;
        this.drop(error.reason);
        return [];
      }
      if (Array.isArray(section)) { this.codes = section; this.unnamed = false; }
      else if ((typeof section === "number" && (!this.codes.length || section !== W.paramsCheck(this.codes)))
               || params !== Boolean(this.codes.length)) {
        this.drop("params");
        this.unnamed = true;
        return [];
      } else if (keyframe) this.unnamed = false;
      let history = [], depth = 0;
      if (!keyframe) {
        const ref = reference(header);
        history = W.bridge(this.held.history(ref), header.back - 1, header.steps);
        depth = this.held.depth(ref) + header.back;
      }
      let levels;
      try {
        levels = W.decodeFrames(body, header.count, history, keyframe, models, this.codes);
      } catch (error) {
        if (!(error instanceof W.WireError)) throw error;
        this.drop(error.reason);
        return [];
      }
      const runs = [];
      levels.forEach((row, i) => {
        const index = mod(header.first + i);
        if (this.held.has(index) && this.held.row(index).every((v, c) => v === row[c])) return;
        this.held.put(index, row, depth + i);
        const lastRun = runs[runs.length - 1];
        if (lastRun && lastRun[0] + lastRun[1].length === i) lastRun[1].push(row);
        else runs.push([i, [row]]);
        this.ackDue = true;
        if (this.ack === null || behind(this.ack, index)) this.ack = index;
      });
      if (keyframe) for (const first of [...this.waiting.keys()]) if (behind(first, header.first)) this.waiting.delete(first);
      this.frameMark = unwrap(header.first, this.frameMark);
      this.timeMark = unwrap(header.time, this.timeMark);
      const filled = (i, count) => {
        if (seen === null) return 0;
        let n = 0;
        for (let k = 0; k < count; k++) if (behind(mod(header.first + i + k), seen)) n++;
        return n;
      };
      return runs.map(([i, rows]) => ({first: this.frameMark[1] + i, time: this.timeMark[1] / 1e3 + i / header.rate,
        rate: header.rate, values: rows.map((r) => r.map((v) => v / header.steps)), arrival, codes: this.codes,
        run: this.run, filled: filled(i, rows.length)}));
    }

    unpackParams(header, body) {
      // stream/wire.py unpack_params: [list of codes | check byte | null, the coded frames]
      if (!(header.flags & C.KEYFRAME)) return [null, body];
      if (!(header.flags & C.PARAMS)) return [[], body];
      if (!body.length) throw new W.WireError("malformed", "a keyframe packet with parameters and no list or check of them");
      if (!(header.flags & C.NAMED)) return [body[0], body.subarray(1)];
      const size = body[0];
      const bytes = body.subarray(1, 1 + size);
      if (bytes.some((b) => b > 127)) throw new W.WireError("malformed", "a parameter list that is not ASCII");
      const codes = String.fromCharCode(...bytes).split(" ");
      if (size === 0 || body.length < 1 + size || codes.length > C.MAX_EXTRA || !codes.every(Boolean)) {
        throw new W.WireError("malformed", "a parameter list that does not fit its packet");
      }
      return [codes, body.subarray(1 + size)];
    }
  }

  window.toonStream = {StreamReader, FrameStore};
})();
