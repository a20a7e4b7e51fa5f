// The one module that shows a face on a page (the studio, the room's viewer page): the server
// draws each frame as SVG (toon/svg.py, a line for each drawn item); a page is sent either the whole
// drawing ({svg}) or only the lines that changed since the frame before ({lines: {index: line}}).
"use strict";
(() => {
  class Drawing {
    // a face shown in `container` (an element it fills with the drawing)
    constructor(container) {
      this.container = container;
      this.lines = [];
      this.held = false;  // held: frames still patch the lines, the picture stays
      this.stale = false;  // lines changed since the picture was last drawn
    }

    show(frame) {
      // draw a frame: {svg} replaces the drawing, {lines} patches the last one
      let changed = true;
      if (frame.svg !== undefined) this.lines = frame.svg.split("\n");
      else {
        const lines = Object.entries(frame.lines || {});
        for (const [index, line] of lines) this.lines[Number(index)] = line;
        changed = lines.length > 0;
      }
      this.stale = this.stale || changed;
      if (this.held || (!this.stale && this.container.firstElementChild)) return this.container.firstElementChild;
      this.stale = false;
      this.container.innerHTML = this.lines.join("\n");
      return this.container.firstElementChild;
    }
  }

  async function inflate(data) {
    // a deflated (zlib) message's JSON
    const stream = new Blob([data]).stream().pipeThrough(new DecompressionStream("deflate"));
    return JSON.parse(await new Response(stream).text());
  }

  window.toonDraw = {Drawing, inflate};
})();
