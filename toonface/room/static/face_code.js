// The performer page's compact frames (toonface/room/performers.py's module docstring has the layout, and
// PageCodes reads them): the head turn as a quaternion and, of the scores the server's mapping reads, the
// ones that changed since the frame before, in 255ths. About 30 bytes a frame, where JSON took 2 kB.
export const FACE = 1;
export const NO_FACE = 2;
const LONG_STEP = 0xffff;

export function turnQuaternion(data) {
  // the unit quaternion [x, y, z] (w >= 0) of MediaPipe's transformation matrix, 16 numbers by columns
  // (WebGL's order), its scale divided out; R[r][c] is data[c * 4 + r]
  const r = (row, col) => data[col * 4 + row];
  const scale = Math.cbrt(r(0, 0) * (r(1, 1) * r(2, 2) - r(1, 2) * r(2, 1))
    - r(0, 1) * (r(1, 0) * r(2, 2) - r(1, 2) * r(2, 0)) + r(0, 2) * (r(1, 0) * r(2, 1) - r(1, 1) * r(2, 0)));
  const m = (row, col) => r(row, col) / scale;
  const trace = m(0, 0) + m(1, 1) + m(2, 2);
  let q;  // [x, y, z, w], Shepperd's choice of the largest term
  if (trace > 0) {
    const s = 2 * Math.sqrt(trace + 1);
    q = [(m(2, 1) - m(1, 2)) / s, (m(0, 2) - m(2, 0)) / s, (m(1, 0) - m(0, 1)) / s, s / 4];
  } else if (m(0, 0) > m(1, 1) && m(0, 0) > m(2, 2)) {
    const s = 2 * Math.sqrt(1 + m(0, 0) - m(1, 1) - m(2, 2));
    q = [s / 4, (m(0, 1) + m(1, 0)) / s, (m(0, 2) + m(2, 0)) / s, (m(2, 1) - m(1, 2)) / s];
  } else if (m(1, 1) > m(2, 2)) {
    const s = 2 * Math.sqrt(1 + m(1, 1) - m(0, 0) - m(2, 2));
    q = [(m(0, 1) + m(1, 0)) / s, s / 4, (m(1, 2) + m(2, 1)) / s, (m(0, 2) - m(2, 0)) / s];
  } else {
    const s = 2 * Math.sqrt(1 + m(2, 2) - m(0, 0) - m(1, 1));
    q = [(m(0, 2) + m(2, 0)) / s, (m(1, 2) + m(2, 1)) / s, s / 4, (m(1, 0) - m(0, 1)) / s];
  }
  const norm = Math.hypot(...q) * (q[3] < 0 ? -1 : 1);
  return q.slice(0, 3).map((v) => v / norm);
}

export class FaceCoder {
  // one socket's frames, in order: NAMES are the scores the server asked for, in its order
  constructor(names) {
    this.names = names;
    this.levels = new Uint8Array(names.length);  // what the server holds for each score
    this.ms = 0;
  }

  encode(ms, scores, matrix) {
    // one frame at MS (since the page started, increasing) as an ArrayBuffer: SCORES an object of
    // blendshape names and values, MATRIX the 16 numbers, or both null where no face is in view
    const now = Math.max(Math.round(ms), this.ms);
    const step = now - this.ms;
    const head = step < LONG_STEP ? 3 : 7;
    let changed = [];
    const size = Math.ceil(this.names.length / 8);
    if (scores) {
      changed = this.names.map((name, i) => [i, Math.round(Math.min(Math.max(scores[name] || 0, 0), 1) * 255)])
        .filter(([i, level]) => level !== this.levels[i]);
    }
    const bytes = new Uint8Array(head + (scores ? 6 + size + changed.length : 0));
    const view = new DataView(bytes.buffer);
    view.setUint8(0, scores ? FACE : NO_FACE);
    view.setUint16(1, Math.min(step, LONG_STEP), true);
    if (head === 7) view.setUint32(3, now, true);
    this.ms = now;
    if (!scores) return bytes.buffer;
    turnQuaternion(matrix).forEach((v, k) => view.setInt16(head + 2 * k, Math.round(v * 32767), true));
    changed.forEach(([i, level], k) => {
      bytes[head + 6 + (i >> 3)] |= 1 << (i & 7);
      bytes[head + 6 + size + k] = level;
      this.levels[i] = level;
    });
    return bytes.buffer;
  }
}
