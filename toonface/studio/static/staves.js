// The staves' knot panel: the knot picked on a staff, its time and value shown and typed in; every
// change is the server's knot move (toonface/studio/editor.py), as a drag is. And Insert: a motion
// or an expression put in at the cursor as knots (StudioSession.insert_motion).
"use strict";
(() => {
  const el = (id) => document.getElementById(id);

  function picked() {
    // [code, index, [t, v]] of the picked knot, where it still exists
    if (!editor.picked || !editor.state) return null;
    const [code, index] = editor.picked;
    const knot = (editor.state.knots[code] || [])[index];
    return knot ? [code, index, knot] : null;
  }

  editor.onRender = () => {
    if (editor.follow) editor.follow();
    const knot = picked();
    el("knot-edit").hidden = knot === null;
    if (!knot) return;
    const [code, index, [t, v, ease]] = knot;
    el("knot-name").textContent = `${code} knot ${index + 1}`;
    const last = index === editor.state.knots[code].length - 1;
    el("knot-ease").checked = Boolean(ease);
    el("knot-ease").disabled = last;  // the last knot starts no segment
    el("knot-ease-label").title = last ? "The last knot starts no segment to ease"
      : "Ease the segment to the next knot: slow out of this one, slow into the next (linear when unticked)";
    for (const [id, value] of [["knot-t", t], ["knot-v", v]]) {
      if (document.activeElement === el(id)) continue;
      el(id).value = value.toFixed(3);
      el(id).dataset.shown = el(id).value;  // what was shown: left as it is, the knot's own value stays
    }
  };

  function read(id, exact) {
    const field = el(id);
    if (field.value.trim() === "") return NaN;  // emptied: nothing to move to yet
    return field.value === field.dataset.shown ? exact : Number(field.value);
  }

  function typed() {
    const knot = picked();
    if (!knot) return;
    const t = read("knot-t", knot[2][0]);
    const v = read("knot-v", knot[2][1]);
    if (!Number.isFinite(t) || !Number.isFinite(v)) return;
    studio.send({op: "knot", action: "move", code: knot[0], index: knot[1], t, v});
  }
  const previousHello = studio.onHello;
  studio.onHello = (hello) => {  // the motions and expressions to insert, as test mode lists them
    if (previousHello) previousHello(hello);
    const names = [...hello.motions, ...hello.expressions];
    el("insert-name").replaceChildren(...names.map((name) => new Option(name, name)));
  };
  el("insert").addEventListener("click", () => studio.send({op: "insert", name: el("insert-name").value}));

  // Shift-drag on the staves draws a box: its time span becomes the selection and the staves it
  // crosses the chosen ones, for cut, copy, paste, scale and flip.
  let box = null;
  editor.startBox = (event, svg) => {
    const origin = svg.getBoundingClientRect();
    box = {x: event.clientX, y: event.clientY, left: origin.left, band: document.createElement("div")};
    box.band.id = "box";
    document.body.append(box.band);
    drawBox(event);
    event.preventDefault();
  };

  function drawBox(event) {
    const [x0, x1] = [Math.min(box.x, event.clientX), Math.max(box.x, event.clientX)];
    const [y0, y1] = [Math.min(box.y, event.clientY), Math.max(box.y, event.clientY)];
    Object.assign(box.band.style, {left: `${x0}px`, top: `${y0}px`, width: `${x1 - x0}px`, height: `${y1 - y0}px`});
    return [x0, x1, y0, y1];
  }

  document.addEventListener("pointermove", (event) => { if (box) drawBox(event); });
  document.addEventListener("pointerup", (event) => {
    if (!box) return;
    const [x0, x1, y0, y1] = drawBox(event);
    box.band.remove();
    const duration = editor.state.duration;
    const left = box.left;
    const t = (x) => Math.max(0, Math.min(duration, (x - left) / editor.zoom));
    box = null;
    const crossed = [];
    for (const [code, svg] of editor.staves) {
      const row = svg.getBoundingClientRect();
      if (row.height > 0 && row.bottom > y0 && row.top < y1) crossed.push(code);
    }
    if (t(x1) - t(x0) <= 0 || !crossed.length) return;
    for (const choose of document.querySelectorAll("#staves input.choose")) {
      choose.checked = crossed.includes(choose.dataset.code);
    }
    editor.selection = [t(x0), t(x1)];
    editor.render();
  });

  // The performer's video, where the animation was tracked from one: a small view in step with the cursor.
  const video = el("performer-video");
  let shown = null;
  function follow() {
    const state = editor.state;
    const name = state && state.video;
    if (name !== shown) {  // opened another take (or none)
      shown = name;
      video.hidden = !name;
      if (name) video.src = `/performer-video?${encodeURIComponent(name)}&${Date.now()}`;
      else video.removeAttribute("src");
    }
    if (!name || video.readyState < 1) return;
    if (state.playing) {
      if (video.paused) video.play().catch(() => {});
      if (Math.abs(video.currentTime - state.cursor) > 0.15) video.currentTime = state.cursor;  // drifted
    } else {
      if (!video.paused) video.pause();
      if (Math.abs(video.currentTime - state.cursor) > 0.02) video.currentTime = state.cursor;
    }
  }
  editor.follow = follow;
  const previousFrame = studio.onFrame;
  studio.onFrame = (frame) => {
    if (previousFrame) previousFrame(frame);
    follow();
  };
  video.addEventListener("loadedmetadata", follow);

  el("knot-ease").addEventListener("change", () => {
    const knot = picked();
    if (knot) studio.send({op: "knot", action: "ease", code: knot[0], index: knot[1], ease: el("knot-ease").checked});
  });
  el("knot-t").addEventListener("change", typed);
  el("knot-v").addEventListener("change", typed);
})();
