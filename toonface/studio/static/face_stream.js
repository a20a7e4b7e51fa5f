// A performer's motor stream drawn in the page: its packets read (stream_reader.js), its frames
// played out at the screen's rate a little behind the newest (linear between frames, the last
// held where the stream stalls), the face's physics run on what is drawn (physics.js), and the
// face drawn from its web rig (rig.js) into a draw.js Drawing. Acknowledgements and keyframe
// requests go back through `send`, so the performer's sender adapts to this page as to `receive`.
"use strict";
(() => {
  const KEEP_SECONDS = 2.0;  // frames kept to play from
  const ASK_EVERY = 0.25;  // seconds between keyframe requests while one is wanted

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
      this.frames = [];  // {time (sender's clock, s), row (the rig's columns)}
      this.offset = Infinity;  // arrival less capture time, the least seen: the link's delay at best
      this.rate = 60;
      this.run = -1;
      this.asked = -Infinity;
      this.drawn = 0;
      this.held = 0;  // frames drawn past the newest frame (the stream stalled or lost it)
      this.last = null;  // the row last drawn
      this.svg = "";
      this.received = 0;
    }

    feed(bytes, now) {
      // a packet of this performer's stream, arrived at `now` (s, the page's clock)
      this.received = now;
      for (const f of this.reader.read(bytes, now)) {
        if (f.run !== this.run) { this.frames = []; this.offset = Infinity; this.run = f.run; }
        this.rate = f.rate;
        f.values.forEach((values, k) => {
          const time = f.time + k / f.rate;
          this.offset = Math.min(this.offset, now - time);
          this.frames.push({time, row: this.row(values, f.codes)});
        });
      }
      this.frames.sort((a, b) => a.time - b.time);
      const newest = this.frames.length ? this.frames[this.frames.length - 1].time : 0;
      while (this.frames.length > 2 && this.frames[0].time < newest - KEEP_SECONDS) this.frames.shift();
      const ack = this.reader.takeAck();
      if (ack) this.send(ack);
      if (this.reader.wantKeyframe && now - this.asked >= ASK_EVERY) {
        this.asked = now;
        this.send(this.reader.keyframeRequest());
      }
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
      if (!this.frames.length) return false;
      const play = now - this.offset - 1.5 / this.rate - 0.02;  // a frame and a half behind, and jitter's margin
      const frames = this.frames;
      let row;
      if (play >= frames[frames.length - 1].time) {
        row = frames[frames.length - 1].row;
        this.held += 1;
      } else if (play <= frames[0].time) {
        row = frames[0].row;
      } else {
        const k = frames.findIndex((f) => f.time > play);
        const a = frames[k - 1], b = frames[k], share = (play - a.time) / (b.time - a.time);
        row = a.row.map((v, c) => v + (b.row[c] - v) * share);
      }
      const moved = this.motion.frame(now, row);
      this.last = moved;
      const svg = this.rig.svg(moved, this.size);
      if (svg !== this.svg) {
        this.svg = svg;
        this.drawing.show({svg});
      }
      this.drawn += 1;
      return true;
    }
  }

  window.toonFaceStream = {FaceStream};
})();
