// The motor stream read in the page: the packets `receive` reads (stream/framing.py's headers and
// checks, stream/wire.py's coded frames, stream/rangecode.py's arithmetic code), checked,
// de-duplicated, re-ordered and decoded as stream/reader.py's StreamReader does, with the same
// acknowledgements and keyframe requests back. One rule each: the constants and the order of
// every step are the Python's, and tests/stream/test_stream_js.py holds the two readers together
// on the same packets (loss, re-ordering, parameters, replays).
"use strict";
(() => {
  const VERSION = 5, WRAP = 2 ** 32;
  const KEYFRAME = 1, SEALED = 2, KEY_REQUEST = 4, ACK = 8, PARAMS = 16, NAMED = 32, LONG = 64, REGULAR = 128;
  const MOTORS = 21, MAX_FRAMES = 32, MAX_EXTRA = 32, CHECK = 2, SEAL = 16, KEEP = 255;
  const ANCHOR_SECONDS = 1.0, ANCHOR_FRAMES = 100, REPLAY_WINDOW = 64, SESSIONS_KEPT = 32;
  const ACK_INTERVAL = 1.0, KEY_WAIT = 0.2, LOSS_SECONDS = 2.0, ACK_BITS = 32, DEFAULT_STEPS = 100;
  const DECAY = [0.09, 0.21, 0.30, 0.45, 0.53, 0.66], HOLD_BELOW = 3;
  const MAX_PACKET = 22 + MAX_FRAMES * MOTORS * 2 + 16 + 64 + MAX_EXTRA * (MAX_FRAMES * 2 + 17);
  // toon/motors.py extra_rest: the standard parameters' rests; any other rests at 0.5
  const EXTRA_REST = {HT: 0.5, UL: 0.0, CP: 0.0, JS: 0.5, PERK: 0.0};

  const roundEven = (x) => (Math.abs(x % 1) === 0.5 ? 2 * Math.round(x / 2) : Math.round(x));  // Python's round()
  const mod = (x) => ((x % WRAP) + WRAP) % WRAP;
  const behind = (index, reference) => mod(reference - index) < WRAP / 2;

  class WireError extends Error {
    constructor(reason, message) { super(message); this.reason = reason; }
  }

  const CRC = (() => {
    const table = new Uint32Array(256);
    for (let n = 0; n < 256; n++) {
      let c = n;
      for (let k = 0; k < 8; k++) c = c & 1 ? 0xEDB88320 ^ (c >>> 1) : c >>> 1;
      table[n] = c >>> 0;
    }
    return table;
  })();

  function crc32(bytes) {
    let c = 0xFFFFFFFF;
    for (const b of bytes) c = CRC[(c ^ b) & 0xFF] ^ (c >>> 8);
    return (c ^ 0xFFFFFFFF) >>> 0;
  }

  function pairwiseSum(a, lo, n) {
    // numpy's pairwise summation, so that a model's counts are the Python's to the last one
    if (n < 8) { let r = 0; for (let i = lo; i < lo + n; i++) r += a[i]; return r; }
    if (n <= 128) {
      const r = a.slice(lo, lo + 8);
      let i = 8;
      for (; i < n - (n % 8); i += 8) for (let j = 0; j < 8; j++) r[j] += a[lo + i + j];
      let sum = ((r[0] + r[1]) + (r[2] + r[3])) + ((r[4] + r[5]) + (r[6] + r[7]));
      for (; i < n; i++) sum += a[lo + i];
      return sum;
    }
    let half = Math.floor(n / 2);
    half -= half % 8;
    return pairwiseSum(a, lo, half) + pairwiseSum(a, lo + half, n - half);
  }

  class Model {
    // a static distribution over 0..len-1 (stream/rangecode.py Model)
    constructor(freq) {
      this.freq = freq;
      this.cum = [0];
      for (const f of freq) this.cum.push(this.cum[this.cum.length - 1] + f);
      this.total = this.cum[this.cum.length - 1];
      this.big = {cum: this.cum.map(BigInt), freq: freq.map(BigInt), total: BigInt(this.total)};
    }

    static laplace(size, centre, decay, precision = 1 << 16) {
      const p = Array.from({length: size}, (_, s) => decay ** Math.abs(s - centre));
      const sum = pairwiseSum(p, 0, size);
      return new Model(p.map((x) => 1 + Math.floor(x / sum * (precision - size))));
    }
  }

  class Decoder {
    // the arithmetic code read back symbol by symbol, exactly (BigInt)
    constructor(bytes) {
      let value = 0n;
      for (const b of bytes) value = (value << 8n) | BigInt(b);
      this.value = value;
      this.bits = BigInt(8 * bytes.length);
      this.low = 0n; this.width = 1n; this.scale = 1n;
    }

    decode(model) {
      const {cum, freq, total} = model.big;
      const rest = this.value * this.scale * total - ((this.low * total) << this.bits);
      const unit = this.width << this.bits;
      let q = rest / unit;
      if (rest < 0n && q * unit !== rest) q -= 1n;  // floor
      let lo = 0, hi = cum.length;  // bisect_right
      while (lo < hi) { const mid = (lo + hi) >> 1; if (q < cum[mid]) hi = mid; else lo = mid + 1; }
      const symbol = Math.min(Math.max(lo - 1, 0), freq.length - 1);
      this.low = this.low * total + cum[symbol] * this.width;
      this.width *= freq[symbol];
      this.scale *= total;
      return symbol;
    }
  }

  class Models {
    constructor(steps) {
      this.steps = steps;
      this.flat = new Model(new Array(steps + 1).fill(1));
      this.residual = DECAY.map((d) => Model.laplace(2 * steps + 1, steps, d));
    }
  }

  function predict(chain, steps) {
    // each value's predicted level and activity context from the last one to three frames
    const last = chain[chain.length - 1], n = last.length, guess = new Array(n), context = new Array(n);
    for (let c = 0; c < n; c++) {
      const d1 = chain.length > 1 ? last[c] - chain[chain.length - 2][c] : 0;
      const d2 = chain.length > 2 ? chain[chain.length - 2][c] - chain[chain.length - 3][c] : 0;
      const activity = Math.abs(d1) + Math.abs(d2);
      const g = activity < HOLD_BELOW ? last[c] : last[c] + Math.floor((5 * d1 + 2 * d2 + 5) / 10);
      guess[c] = Math.min(Math.max(g, 0), steps);
      context[c] = Math.min(activity, DECAY.length - 1);
    }
    return [guess, context];
  }

  function bridge(history, gap, steps) {
    let chain = history.slice(-3);
    for (let k = 0; k < gap; k++) chain = [...chain.slice(-2), predict(chain, steps)[0]];
    return chain.slice(-3);
  }

  function decodeFrames(body, count, history, keyframe, models, codes) {
    const decoder = new Decoder(body), steps = models.steps;
    let chain = keyframe ? [] : history.slice(-3);
    const rests = codes.map((code) => roundEven((EXTRA_REST[code] ?? 0.5) * steps));
    const out = [];
    for (let f = 0; f < count; f++) {
      let row;
      if (!chain.length) {
        row = Array.from({length: MOTORS}, () => decoder.decode(models.flat));
        for (const rest of rests) row.push(rest + decoder.decode(models.residual[DECAY.length - 1]) - steps);
      } else {
        const [guess, context] = predict(chain, steps);
        row = guess.map((g, c) => g + decoder.decode(models.residual[context[c]]) - steps);
      }
      if (Math.min(...row) < 0 || Math.max(...row) > steps) throw new WireError("malformed", "a coded value outside the quantisation range");
      out.push(row);
      chain = [...chain.slice(-2), row];
    }
    return out;
  }

  function paramsCheck(codes) {
    return crc32(new TextEncoder().encode(codes.join(" "))) & 0xFF;
  }

  function longHeader(h) {
    // stream/framing.py _long: the full header in its long form (what the check covers)
    const out = new Uint8Array(22), view = new DataView(out.buffer);
    view.setUint8(0, (h.flags | LONG) & ~REGULAR & 0xFF);
    view.setUint16(1, h.stream & 0xFFFF, true);
    view.setUint8(3, VERSION);
    view.setUint32(4, mod(h.sequence), true);
    view.setUint32(8, mod(h.first), true);
    view.setUint32(12, mod(h.time), true);
    view.setUint8(16, h.count);
    view.setUint8(17, h.usual);
    view.setUint8(18, h.steps);
    view.setUint16(19, Math.round(h.rate * 100), true);
    view.setUint8(21, h.flags & KEYFRAME ? 0 : h.back);
    return out;
  }

  const reply = (flags, stream, first = 0, held = 0) =>
    ({flags, sequence: 0, first: mod(first), time: held, count: 0, steps: 1, rate: 1.0, back: 0, stream: stream & 0xFFFF, usual: 0});

  function withCheck(head, full, body) {
    const all = new Uint8Array(full.length + body.length);
    all.set(full); all.set(body, full.length);
    const check = crc32(all) & 0xFFFF, out = new Uint8Array(head.length + body.length + CHECK);
    out.set(head); out.set(body, head.length);
    out[out.length - 2] = check & 0xFF; out[out.length - 1] = check >> 8;
    return out;
  }

  function sealReply(flags, stream, first = 0, held = 0, key = null) {
    // an acknowledgement or keyframe request: a CRC check, or sealed with `key`
    flags = (flags & ~(SEALED | LONG | REGULAR)) | (key ? SEALED : 0);
    let head;
    if (flags & ACK) {
      head = new Uint8Array(9);
      const view = new DataView(head.buffer);
      view.setUint8(0, flags); view.setUint16(1, stream & 0xFFFF, true);
      view.setUint16(3, first & 0xFFFF, true); view.setUint32(5, held >>> 0, true);
    } else {
      head = new Uint8Array([flags, stream & 0xFF, (stream >> 8) & 0xFF]);
    }
    const full = longHeader(reply(flags, stream, first, held));
    if (!key) return withCheck(head, full, new Uint8Array(0));
    const tag = key.seal(full.subarray(0, 12), new Uint8Array(0), full), out = new Uint8Array(head.length + tag.length);
    out.set(head); out.set(tag, head.length);
    return out;
  }

  async function streamKey(secret, base = "/web/noble") {
    // the stream's cipher for a shared secret (bytes): AES-256-GCM-SIV under a key derived by
    // HKDF-SHA256, as stream/framing.py StreamKey; noble's audited code, served by the room server
    if (secret.length < 16) throw new Error("a key needs at least 16 bytes");
    let modules;
    try {
      modules = await Promise.all([
        import(`${base}/ciphers/aes.js`), import(`${base}/hashes/hkdf.js`), import(`${base}/hashes/sha2.js`)]);
    } catch {
      throw new Error("this page cannot open sealed streams: @noble/ciphers and @noble/hashes are not served "
        + "here (make browser installs them beside the room server)");
    }
    const [{gcmsiv}, {hkdf}, {sha256}] = modules;
    const derived = hkdf(sha256, secret, undefined, new TextEncoder().encode(`toonface stream ${VERSION}`), 32);
    return {open: (nonce, data, aad) => gcmsiv(derived, nonce, aad).decrypt(data),
      seal: (nonce, data, aad) => gcmsiv(derived, nonce, aad).encrypt(data)};
  }

  function signed(value, bits) {
    const size = 2 ** bits;
    value = ((value % size) + size) % size;
    return value >= size / 2 ? value - size : value;
  }

  const restore = (low, near, bits) => mod(near + signed(low - near, bits));

  function openPacket(data, anchor, key = null) {
    // a datagram's full header and body, checked or opened with `key` (streamKey's), as
    // stream/framing.py open_packet does
    if (data.length > MAX_PACKET || data.length < 3 + CHECK) throw new WireError("size", `a packet of ${data.length} bytes`);
    const flags = data[0], view = new DataView(data.buffer, data.byteOffset, data.byteLength);
    if (Boolean(flags & SEALED) !== Boolean(key)) {
      throw new WireError("tag", key ? "an unsealed packet" : "a sealed packet and no key to open it");
    }
    let header, size;
    const need = (n) => { if (data.length < n) throw new WireError("size", "a packet shorter than its header"); };
    if (flags & ACK) {
      need(9);
      header = reply(flags, view.getUint16(1, true), restore(view.getUint16(3, true), anchor ? anchor.first : 0, 16), view.getUint32(5, true));
      size = 9;
    } else if (flags & KEY_REQUEST) {
      header = reply(flags, view.getUint16(1, true));
      size = 3;
    } else if (flags & LONG) {
      need(22);
      if (data[3] !== VERSION) throw new WireError("version", `stream version ${data[3]} (this reads ${VERSION})`);
      header = {flags, stream: view.getUint16(1, true), sequence: view.getUint32(4, true), first: view.getUint32(8, true),
        time: view.getUint32(12, true), count: data[16], usual: data[17], steps: data[18],
        rate: view.getUint16(19, true) / 100, back: data[21]};
      size = 22;
    } else {
      if (!anchor) throw new WireError("unanchored", "a short header and no packet before it to read it against");
      need(5);
      size = 5;
      let count = anchor.usual, back = 1;
      if (!(flags & REGULAR)) { need(6); count = data[5] >> 4; back = data[5] & 0xF; size = 6; }
      const first = restore(data[4], anchor.first, 8);
      const time = mod(anchor.time + Math.round(signed(first - anchor.longFrame, 32) * 1000 / anchor.rate));
      header = {flags, stream: view.getUint16(1, true), sequence: restore(data[3], anchor.sequence, 8), first, time,
        count, usual: anchor.usual, steps: anchor.steps, rate: anchor.rate, back};
    }
    const tail = key ? SEAL : CHECK;
    if (data.length < size + tail) throw new WireError("size", "a packet with no room for its header and tag");
    const short = !(flags & (LONG | ACK | KEY_REQUEST));
    const full = longHeader(short ? {...header, time: 0} : header);  // a short header's time is not sent
    let body;
    if (key) {
      try {
        body = key.open(full.subarray(0, 12), data.subarray(size), full);
      } catch {
        throw new WireError("tag", "the packet does not open with this key (another key, corrupted, forged or replayed)");
      }
    } else {
      body = data.subarray(size, data.length - CHECK);
      const expected = withCheck(new Uint8Array(0), full, body);
      if (expected[expected.length - 2] !== data[data.length - 2] || expected[expected.length - 1] !== data[data.length - 1]) {
        throw new WireError("tag", "the packet's check does not match (corrupted, or replayed from long ago)");
      }
    }
    if (header.count > MAX_FRAMES || header.steps < 1 || header.rate <= 0 || (header.count && !(flags & KEYFRAME) && header.back === 0)) {
      throw new WireError("malformed", `a header with ${header.count} frames`);
    }
    return [header, body];
  }

  window.toonWire = {WireError, Model, Models, Decoder, decodeFrames, bridge, openPacket, sealReply, streamKey, paramsCheck,
    behind, mod, crc32, EXTRA_REST, constants: {WRAP, KEYFRAME, SEALED, KEY_REQUEST, ACK, PARAMS, NAMED, LONG, REGULAR, MOTORS,
      MAX_EXTRA, KEEP, ANCHOR_SECONDS, ANCHOR_FRAMES, REPLAY_WINDOW, SESSIONS_KEPT, ACK_INTERVAL, KEY_WAIT,
      LOSS_SECONDS, ACK_BITS, DEFAULT_STEPS}};
})();
