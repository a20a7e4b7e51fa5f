// A performer's motor stream drawn in the page: its packets read (stream_reader.js), its frames
// played out at the screen's rate by the jitter buffer and concealment `receive` uses
// (playout.js), the face's physics run on what is drawn (physics.js), and the face drawn from its
// web rig (rig.js) into a draw.js Drawing. Acknowledgements and keyframe requests go back through
// `send`, so the performer's sender adapts to this page as to `receive`.
"use strict";
(() => {
  const ASK_EVERY = 0.25;  // seconds between keyframe requests while one is wanted ...
  const ASK_AT_MOST = 2.0;  // ... doubling with each while no packet has opened (another key's), up to this

  class FaceStream {
    // `rig`: a toonRig.Rig; `drawing`: a toonDraw.Drawing; `send(bytes)`: replies to the performer;
    // `key`: toonWire.streamKey's, for a sealed stream
    constructor(rig, drawing, send, key = null, size = [512, 512]) {
      this.rig = rig;
      this.drawing = drawing;
      this.send = send;
      this.size = size;
      this.reader = new toonStream.StreamReader(key);
      this.motion = new toonPhysics.Motion(rig.data.physics);
      const neutral = rig.data.neutral, declared = {};
      rig.codes.slice(21).forEach((code, i) => { declared[code] = neutral[21 + i]; });
      this.playout = new toonPlayout.Playout(neutral.slice(0, 21), {declared});
      this.asked = -Infinity;
      this.unanswered = 0;  // keyframe requests made while no packet of the stream opened
      this.last = null;  // the row last drawn (the rig's columns)
      this.svg = "";
      this.received = -Infinity;  // when a packet last came
    }

    feed(bytes, now) {
      // a packet of this performer's stream, arrived at `now` (s, the page's clock)
      this.received = now;
      for (const frames of this.reader.read(bytes, now)) this.playout.add(frames);
      const ack = this.reader.takeAck();
      if (ack) this.send(ack);
      const unanswered = this.reader.packets ? 0 : this.unanswered;
      if (this.reader.wantKeyframe && now - this.asked >= Math.min(ASK_EVERY * 2 ** unanswered, ASK_AT_MOST)) {
        this.asked = now;
        this.unanswered = this.reader.packets ? 0 : unanswered + 1;
        this.send(this.reader.keyframeRequest());
      }
    }

    quality(offset = 0) {
      // what the caption says: latency (ms, null where the sender's clock is another than this one
      // less OFFSET seconds), loss and concealment (% of packets, % of frames shown)
      const r = this.reader, s = this.playout.stats, latency = this.playout.latency(offset);
      const shown = s.live + s.concealed + s.recovering;
      return {latency: latency === null ? null : Math.round(latency * 1000),
        loss: r.packets ? 100 * r.lost / (r.packets + r.lost) : 0, concealed: shown ? 100 * s.concealed / shown : 0};
    }

    row(values, codes) {
      // a frame's values in the rig's columns: the 21, then the parameters the face has (those
      // the stream lacks at the face's rest; those the face lacks are not drawn)
      const row = this.rig.data.neutral.slice();
      for (let i = 0; i < 21; i++) row[i] = values[i];
      codes.forEach((code, j) => {
        const column = this.rig.codes.indexOf(code);
        if (column >= 0) row[column] = values[21 + j];
      });
      return row;
    }

    draw(now) {
      // draw the frame due at `now` (s); false while nothing has come
      if (this.playout.anchor === null) return false;
      const [values] = this.playout.valuesAt(now);
      const moved = this.motion.frame(now, this.row(values, this.playout.codes));
      this.last = moved;
      const svg = this.rig.svg(moved, this.size);
      if (svg !== this.svg) {
        this.svg = svg;
        this.drawing.show({svg});
      }
      return true;
    }
  }

  window.toonFaceStream = {FaceStream};
})();
