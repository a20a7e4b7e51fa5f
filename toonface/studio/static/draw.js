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
    }

    show(frame) {
      // draw a frame: {svg} replaces the drawing, {lines} patches the last one
      if (frame.svg !== undefined) this.lines = frame.svg.split("\n");
      else {
        const changed = Object.entries(frame.lines || {});
        if (!changed.length && this.container.firstElementChild) return this.container.firstElementChild;
        for (const [index, line] of changed) this.lines[Number(index)] = line;
      }
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
