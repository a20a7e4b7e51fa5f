// The Animation Editor's staves (CharToon 3.3): one staff per motor, drawn from the knots the
// server sends; every edit goes to the server (toonface/studio/editor.py), which runs the same
// operations as `toonface anim` and sends the knots back.
(() => {
"use strict";
  const editor = {
    state: null,          // the server's last description of the animation
    zoom: 120,            // pixels per second
    selection: null,      // [start, end] seconds, chosen on the ruler
    picked: null,         // [code, index] of the knot last clicked
    dragging: null,       // [code, index] while a knot is dragged
    staves: new Map(),    // motor code -> its staff's <svg>
    hidden: new Set(),    // motor codes whose staves are hidden
  };
  window.editor = editor;

  const STAFF_HEIGHT = 40;
  const PAD = 4;  // pixels above 1 and below 0
  const STILL = 0.05;  // a motor whose knots span less than this does not move (its group goes last)
  const el = (id) => document.getElementById(id);

  const svgNode = studio.svg;

  const xOf = (t) => t * editor.zoom;
  const yOf = (v) => PAD + (1 - v) * (STAFF_HEIGHT - 2 * PAD);
  const tOf = (x) => Math.max(0, Math.min(editor.state.duration, x / editor.zoom));
  const vOf = (y) => Math.max(0, Math.min(1, 1 - (y - PAD) / (STAFF_HEIGHT - 2 * PAD)));

  function local(event, svg) {
    const box = svg.getBoundingClientRect();
    return [event.clientX - box.left, event.clientY - box.top];
  }

  function chosen() {
    return [...document.querySelectorAll("#staves input.choose:checked")].map((box) => box.dataset.code);
  }

  function span() {
    return editor.selection || [0, editor.state.duration];
  }

  function buildStaves(groups) {
    const holder = el("staves");
    holder.replaceChildren();
    editor.staves.clear();
    for (const [order, group] of groups.entries()) {
      const details = document.createElement("details");
      details.className = "staves";
      details.open = true;
      Object.assign(details.dataset, {order, title: group.title});
      const summary = document.createElement("summary");
      summary.textContent = group.title;
      details.append(summary);
      for (const motor of group.motors) details.append(staff(motor));
      holder.append(details);
    }
    if (editor.state) render();
  }

  function staff(motor) {
    const row = document.createElement("div");
    row.className = "staff";
    row.dataset.code = motor.code;
    row.title = motor.description;
    const label = document.createElement("label");
    label.className = "label";
    const box = Object.assign(document.createElement("input"), {type: "checkbox", className: "choose"});
    box.dataset.code = motor.code;
    box.title = "Choose this staff for cut, copy, paste, scale and flip";
    const hide = Object.assign(document.createElement("button"), {type: "button", textContent: "×", title: "Hide"});
    hide.addEventListener("click", () => { editor.hidden.add(motor.code); row.classList.add("hidden"); });
    const axis = document.createElement("span");
    axis.className = "axis";
    axis.setAttribute("aria-hidden", "true");
    axis.append(Object.assign(document.createElement("span"), {textContent: "1"}),
                Object.assign(document.createElement("span"), {textContent: "0"}));
    const who = document.createElement("span");  // the code, and under it what a designer calls it
    who.className = "who";
    who.append(Object.assign(document.createElement("b"), {textContent: motor.code}));
    if (motor.name && motor.name !== motor.code) who.append(Object.assign(document.createElement("span"), {textContent: motor.name}));
    label.append(box, who, hide, axis);
    const svg = svgNode("svg", {"data-code": motor.code});
    svg.addEventListener("dblclick", (event) => addKnot(event, motor.code, svg));
    svg.addEventListener("pointerdown", (event) => startDrag(event, motor.code, svg));
    svg.addEventListener("pointermove", (event) => moveDrag(event, svg));
    svg.addEventListener("pointerup", () => { editor.dragging = null; });
    svg.addEventListener("contextmenu", (event) => deleteKnot(event));
    row.append(label, svg);
    editor.staves.set(motor.code, svg);
    return row;
  }

  function render() {
    const state = editor.state;
    const seconds = Math.max(state.duration, editor.sound ? editor.sound.duration : 0);
    const width = Math.max(200, xOf(seconds) + 1);
    const [start, end] = editor.selection || [null, null];
    drawRuler(width);
    drawSound(width);
    for (const [code, svg] of editor.staves) {
      svg.setAttribute("width", width);
      svg.setAttribute("height", STAFF_HEIGHT);
      const parts = gridLines(seconds, width);
      if (start !== null && (chosen().length === 0 || chosen().includes(code))) {
        parts.push(svgNode("rect", {class: "chosen-span", x: xOf(start), y: 0, width: xOf(end - start), height: STAFF_HEIGHT}));
      }
      const knots = state.knots[code] || [];
      if (knots.length === 0) {
        if (state.neutral[code] !== undefined) {  // a staff just made for a new parameter: its rest comes next
          const y = yOf(state.neutral[code]);
          parts.push(svgNode("line", {class: "rest", x1: 0, x2: width, y1: y, y2: y}));
        }
      } else {
        const points = [[0, knots[0][1]]];
        knots.forEach((knot, i) => {
          points.push(knot);
          const next = knots[i + 1];
          if (knot[2] && next && next[0] > knot[0]) {  // an eased segment: its curve (toon/animation.py's smoothstep)
            for (let j = 1; j < 16; j += 1) {
              const u = j / 16;
              points.push([knot[0] + (next[0] - knot[0]) * u, knot[1] + (next[1] - knot[1]) * u * u * (3 - 2 * u)]);
            }
          }
        });
        points.push([state.duration, knots[knots.length - 1][1]]);
        parts.push(svgNode("polyline", {class: "curve", points: points.map(([t, v]) => `${xOf(t)},${yOf(v)}`).join(" ")}));
        knots.forEach(([t, v, ease], index) => {
          const picked = editor.picked && editor.picked[0] === code && editor.picked[1] === index;
          const kind = `knot${picked ? " picked" : ""}${ease ? " eased" : ""}`;
          parts.push(svgNode("circle", {class: kind, cx: xOf(t), cy: yOf(v), r: 4.5,
                                        "data-index": index}));
        });
      }
      const driven = (state.driven || {})[code];  // what the face's physics makes of it: shown, not edited
      if (driven && driven.length > 1) {
        parts.push(svgNode("polyline", {class: "driven", points: driven.map(([t, v]) => `${xOf(t)},${yOf(v)}`).join(" ")}));
      }
      parts.push(svgNode("line", {class: "cursor", x1: xOf(state.cursor), x2: xOf(state.cursor), y1: 0, y2: STAFF_HEIGHT}));
      svg.replaceChildren(...parts);
    }
    if (document.activeElement !== el("duration")) el("duration").value = state.duration;  // not while typed in
    el("undo").disabled = state.undo === 0;
    el("redo").disabled = state.redo === 0;
    el("paste").disabled = state.clipboard === null;
    if (state.path && !el("path").value) el("path").value = state.path;
    el("selection").textContent = editor.selection
      ? `selection ${start.toFixed(2)}–${end.toFixed(2)} s` : `cursor ${state.cursor.toFixed(2)} s`;
    if (editor.onRender) editor.onRender();
  }

  function gridLines(seconds, width) {
    // a staff's grid: its values 0, 0.5 and 1 across, and the ruler's seconds down
    const lines = [0, 0.5, 1].map((v) => svgNode("line", {class: v === 0.5 ? "grid half" : "grid", x1: 0, x2: width,
                                                         y1: yOf(v), y2: yOf(v)}));
    const step = editor.zoom >= 40 ? 1 : 5;
    for (let t = step; t < seconds; t += step) {
      lines.push(svgNode("line", {class: "grid", x1: xOf(t), x2: xOf(t), y1: 0, y2: STAFF_HEIGHT}));
    }
    return lines;
  }

  function drawSound(width) {
    const sound = editor.sound;
    if (!sound) return;
    const wave = el("wave");
    const labels = el("label-track");
    for (const svg of [wave, labels]) svg.setAttribute("width", width);
    const height = 36;
    const step = 1 / sound.per_second;
    const top = sound.high.map((v, i) => `${xOf(i * step)},${(1 - v) * height / 2}`);
    const bottom = sound.low.map((v, i) => `${xOf(i * step)},${(1 - v) * height / 2}`).reverse();
    const parts = [svgNode("polygon", {class: "wave", points: [...top, ...bottom].join(" ")})];
    parts.push(svgNode("line", {class: "cursor", x1: xOf(editor.state.cursor), x2: xOf(editor.state.cursor),
                                y1: 0, y2: height}));
    wave.replaceChildren(...parts);
    // heard: words, a row of phones under them, and a row of the mouth shapes the motors follow
    const rows = 1 + Math.max(0, ...sound.labels.map((label) => label.row || 0));
    const KIND = ["word", "phone", "shape"];
    labels.style.height = `${rows === 1 ? 36 : 4 + 16 * rows}px`;
    labels.replaceChildren(...sound.labels.flatMap((label) => {
      const top = rows === 1 ? 4 : 2 + 16 * (label.row || 0);
      const kind = KIND[label.row || 0] || "word";
      const box = svgNode("rect", {x: xOf(label.start), y: top, width: Math.max(2, xOf(label.end - label.start)),
                                   height: rows === 1 ? 28 : 14, rx: 3, class: kind});
      const text = svgNode("text", {x: xOf(label.start) + 3, y: rows === 1 ? 22 : top + 11, class: kind});
      text.textContent = label.text;
      const title = svgNode("title", {});
      title.textContent = `${label.start.toFixed(2)}–${label.end.toFixed(2)} s: ${label.text}`;
      box.append(title);
      return [box, text];
    }));
  }

  function syncAudio(playing) {
    const audio = el("audio");
    if (!editor.sound) return;
    if (!playing) {
      if (!audio.paused) audio.pause();
      return;
    }
    if (audio.paused || Math.abs(audio.currentTime - editor.state.cursor) > 0.15) {
      audio.currentTime = editor.state.cursor;
    }
    if (audio.paused) audio.play().catch(() => {});
  }

  function drawRuler(width) {
    const ruler = el("ruler");
    ruler.setAttribute("width", width);
    const parts = [];
    const step = editor.zoom >= 200 ? 0.1 : editor.zoom >= 40 ? 0.5 : 1;
    for (let t = 0; t <= editor.state.duration + 1e-9; t += step) {
      const whole = Math.abs(t - Math.round(t)) < 1e-9;
      parts.push(svgNode("line", {class: "tick", x1: xOf(t), x2: xOf(t), y1: whole ? 8 : 15, y2: 22}));
      if (whole) {
        const label = svgNode("text", {class: "tick-label", x: xOf(t) + 2, y: 10});
        label.textContent = `${Math.round(t)} s`;
        parts.push(label);
      }
    }
    if (editor.selection) {
      const [start, end] = editor.selection;
      parts.push(svgNode("rect", {class: "chosen-span", x: xOf(start), y: 0, width: xOf(end - start), height: 22}));
    }
    parts.push(svgNode("line", {class: "cursor", x1: xOf(editor.state.cursor), x2: xOf(editor.state.cursor), y1: 0, y2: 22}));
    ruler.replaceChildren(...parts);
  }

  function knotAt(event) {
    const index = event.target.dataset ? event.target.dataset.index : undefined;
    return index === undefined ? null : Number(index);
  }

  function addKnot(event, code, svg) {
    if (knotAt(event) !== null) return;
    const [x, y] = local(event, svg);
    studio.send({op: "knot", action: "add", code, t: tOf(x), v: vOf(y)});
  }

  function startDrag(event, code, svg) {
    const index = knotAt(event);
    if (event.button === 0 && event.shiftKey && index === null && editor.startBox) {
      editor.startBox(event, svg);  // shift-drag on the staves: a box across them (staves.js)
      return;
    }
    if (index === null || event.button !== 0) return;
    editor.picked = [code, index];
    editor.dragging = [code, index];
    svg.setPointerCapture(event.pointerId);  // the staff keeps the pointer while its knots are redrawn
    event.preventDefault();
    render();
  }

  function moveDrag(event, svg) {
    if (!editor.dragging) return;
    const [code, index] = editor.dragging;
    const [x, y] = local(event, svg);
    studio.send({op: "knot", action: "move", code, index, t: tOf(x), v: vOf(y)});
  }

  function deleteKnot(event) {
    const index = knotAt(event);
    if (index === null) return;
    event.preventDefault();
    const code = event.currentTarget.dataset.code;
    editor.picked = null;
    studio.send({op: "knot", action: "delete", code, index});
  }

  function sliceOp(action, extra = {}) {
    const [start, end] = span();
    studio.send({op: "slice", action, codes: chosen(), start, end, ...extra});
  }

  function rulerDown(event) {
    const [x] = local(event, el("ruler"));
    const t = tOf(x);
    editor.rulerFrom = t;
    editor.selecting = event.shiftKey;  // shift: choose a time slice; else the cursor follows (scrubbing)
    el("ruler").setPointerCapture(event.pointerId);
    if (!event.shiftKey) {
      editor.selection = null;
      studio.send({op: "cursor", t});
    }
  }

  function rulerMove(event) {
    if (editor.rulerFrom === undefined || editor.rulerFrom === null) return;
    const [x] = local(event, el("ruler"));
    const t = tOf(x);
    if (!editor.selecting) {
      studio.send({op: "cursor", t});
    } else if (Math.abs(t - editor.rulerFrom) * editor.zoom > 3) {
      editor.selection = [Math.min(t, editor.rulerFrom), Math.max(t, editor.rulerFrom)];
      render();
    }
  }

  function showTake(take) {
    // a take whose file left its rate or units unsaid: what was read, to be read otherwise
    el("take-ask").hidden = !take;
    if (!take) return;
    const rate = take.ask.includes("rate");
    el("take-said").textContent = rate && take.rate === null ? `${take.name} does not say its frame rate:`
      : `${take.name} read in ${take.units}${rate ? ` at ${take.rate} Hz` : ""} (${take.said}):`;
    el("take-rate-label").hidden = !rate;
    if (take.rate !== null) el("take-rate").value = take.rate;
    el("take-units").value = take.units && [...el("take-units").options].some((o) => o.value === take.units)
      ? take.units : "";
  }

  function orderStaves(state) {
    // an animation opened: the groups whose motors move most first, the still ones last and said
    // so, so that what moves is in sight (a take's brows filled the screen, its MB far below); all
    // stay open, a still motor as easy to key as before
    const holder = el("staves");
    const groups = [...holder.querySelectorAll("details.staves")];
    const span = (code) => {
      const values = (state.knots[code] || []).map((knot) => knot[1]);
      return values.length ? Math.max(...values) - Math.min(...values) : 0;
    };
    const moving = new Map(groups.map((group) => [group, Math.max(0, ...[...group.querySelectorAll(".staff")].map(
      (row) => span(row.dataset.code)))]));
    const any = [...moving.values()].some((most) => most >= STILL);
    groups.sort((a, b) => (any ? moving.get(b) - moving.get(a) : 0) || (a.dataset.order - b.dataset.order));
    for (const group of groups) {
      const still = any && moving.get(group) < STILL;
      group.querySelector("summary").textContent = still ? `${group.dataset.title} (still)` : group.dataset.title;
      holder.append(group);
    }
  }

  editor.show = (state) => {
    const fresh = !editor.state || editor.state.duration !== state.duration;  // opened, new, or made longer
    const source = (st) => `${st.path}|${st.take ? st.take.path : ""}|${st.video}`;  // what the knots came from
    const opened = !editor.state || source(editor.state) !== source(state) || (editor.state.undo > 0 && state.undo === 0);
    showTake(state.take);
    editor.state = state;
    if (editor.selection && editor.selection[1] > state.duration) editor.selection = null;
    if (opened || fresh) orderStaves(state);
    if (fresh) fit();  // the whole animation across the score's width (it renders)
    else render();
  };

  function moveCursor() {
    // playback moves the cursor lines only: redrawing every staff each frame (a mapped take's
    // hundreds of knots) made the page answer a click seconds late, and Pause landed at the end
    const x = xOf(editor.state.cursor);
    for (const line of document.querySelectorAll("#staves line.cursor, #wave line.cursor, #ruler line.cursor")) {
      line.setAttribute("x1", x);
      line.setAttribute("x2", x);
    }
    if (!editor.selection) el("selection").textContent = `cursor ${editor.state.cursor.toFixed(2)} s`;
  }

  studio.onAnimation = editor.show;
  studio.onFrame = (frame) => {
    if (!editor.state) return;
    const moved = frame.cursor !== editor.state.cursor;
    editor.state.playing = frame.playing;
    editor.state.cursor = frame.cursor;  // playback moves the cursor
    syncAudio(frame.playing);
    if (moved) moveCursor();
  };
  const previousDescribe = studio.onHello;
  studio.onHello = (hello) => {
    if (previousDescribe) previousDescribe(hello);
    buildStaves(hello.groups);
  };

  el("ruler").addEventListener("pointerdown", rulerDown);
  el("ruler").addEventListener("pointermove", rulerMove);
  el("ruler").addEventListener("pointerup", () => { editor.rulerFrom = null; });
  el("play").addEventListener("click", () => {
    const [start, end] = editor.selection || [null, null];
    studio.send({op: "playback", action: "play", loop: el("loop").checked, start, end});
  });
  // paused where the page shows the cursor: frames reach a loaded page late, and the user stops what they see
  el("pause").addEventListener("click", () => studio.send({op: "playback", action: "pause", at: editor.state.cursor}));
  el("zoom-in").addEventListener("click", () => { editor.zoom = Math.min(2000, editor.zoom * 1.5); render(); });
  el("show-all").addEventListener("click", () => {
    editor.hidden.clear();
    document.querySelectorAll("#staves .staff.hidden").forEach((row) => row.classList.remove("hidden"));
  });
  el("zoom-out").addEventListener("click", () => { editor.zoom = Math.max(10, editor.zoom / 1.5); render(); });
  el("cut").addEventListener("click", () => { sliceOp("cut"); editor.selection = null; });
  el("copy").addEventListener("click", () => sliceOp("copy"));
  el("flip").addEventListener("click", () => sliceOp("flip"));
  el("scale-time").addEventListener("click", () => sliceOp("scale_time", {factor: Number(el("factor").value)}));
  el("scale-value").addEventListener("click", () => sliceOp("scale_value", {factor: Number(el("factor").value)}));
  el("paste").addEventListener("click", () => {
    const onto = chosen();
    const clip = editor.state.clipboard;
    const elsewhere = clip && onto.length === clip.motors.length && onto.join() !== clip.motors.join();
    studio.send({op: "paste", at: editor.state.cursor, onto: elsewhere ? onto : null});
  });
  el("undo").addEventListener("click", () => studio.send({op: "undo"}));
  el("redo").addEventListener("click", () => studio.send({op: "redo"}));
  el("duration").addEventListener("change", (event) => studio.send({op: "duration", seconds: Number(event.target.value)}));
  el("new").addEventListener("click", () => studio.send({op: "new", seconds: Number(el("duration").value) || 5}));
  editor.open = (path, reading = {}) => {
    // a file of the working folder into the staves; a take or track as knots within the tolerance,
    // a take read in the units and at the rate given where its file does not say them
    editor.opened = path;
    editor.reading = reading;
    studio.send({op: "open", path, tolerance: Number(el("tolerance").value) || 0.01, ...reading});
  };
  el("take-reopen").addEventListener("click", () => {
    const take = editor.state && editor.state.take;
    if (!take) return;
    const reading = {};
    if (el("take-units").value) reading.units = el("take-units").value;
    if (!el("take-rate-label").hidden && el("take-rate").value) reading.rate = Number(el("take-rate").value);
    editor.open(take.path, reading);
  });
  el("open").addEventListener("click", () => editor.open(el("path").value));
  el("simplify").addEventListener("click", () => {
    if (editor.opened && !editor.opened.endsWith(".toml")) editor.open(editor.opened, editor.reading);
    else studio.say("Simplify opens a take or a motor track again: open one first", true);
  });
  el("save").addEventListener("click", () => studio.send({op: "save", path: el("path").value || null}));
  el("sample").addEventListener("click", () => studio.send({op: "sample", path: el("export").value,
                                                            rate: Number(el("rate").value)}));
  el("render").addEventListener("click", () => studio.send({op: "render", path: el("export").value,
                                                            fps: Number(el("rate").value)}));
  studio.handlers.sound = (message) => {
    editor.sound = message;
    editor.soundVersion = (editor.soundVersion || 0) + 1;
    el("audio").src = `/sound.wav?v=${editor.soundVersion}`;
    el("sound-row").hidden = false;
    el("labels-row").hidden = message.labels.length === 0;
    if (editor.state) render();
  };
  el("open-sound").addEventListener("click", () => studio.send({op: "sound", path: el("sound-path").value}));
  el("open-labels").addEventListener("click", () => studio.send({op: "labels", path: el("labels-path").value}));
  el("hear").addEventListener("click", () => studio.send({op: "hear", text: el("hear-words").value || null}));
  studio.handlers.rendering = (message) => {
    const bar = el("render-progress");
    bar.hidden = false;
    bar.max = message.of;
    bar.value = message.frames;
  };
  studio.handlers.rendered = (message) => {
    el("render-progress").hidden = true;
    studio.say(`wrote ${message.path} (${message.frames} frames)`, false);
  };
  function fit() {
    // zoom the staves so the whole animation fits the score's width
    const label = document.querySelector("#staves .staff .label") || document.querySelector("#score .staff .label");
    const room = el("score").clientWidth - (label ? label.getBoundingClientRect().width : 180) - 30;
    if (editor.state && editor.state.duration > 0 && room > 0) {
      editor.zoom = Math.max(10, Math.min(2000, room / editor.state.duration));
    }
    render();
  }
  editor.fit = fit;
  editor.render = () => render();

  document.addEventListener("keydown", (event) => {
    // the studio's shortcuts (listed in its Keys panel)
    const tag = event.target.tagName;
    if (tag === "INPUT" || tag === "SELECT" || tag === "TEXTAREA") return;
    const command = event.ctrlKey || event.metaKey;
    const key = event.key.toLowerCase();
    const faceOpen = el("face-panel").open;
    if ((event.key === "Delete" || event.key === "Backspace") && editor.picked) {
      const [code, index] = editor.picked;
      editor.picked = null;
      studio.send({op: "knot", action: "delete", code, index});
    } else if (command && (key === "z" || key === "y")) {
      const redo = event.shiftKey || key === "y";
      event.preventDefault();
      if (faceOpen) el(redo ? "face-redo" : "face-undo").click();
      else studio.send({op: redo ? "redo" : "undo"});
    } else if (command && (key === "c" || key === "x" || key === "v") && !String(window.getSelection())) {
      event.preventDefault();
      el({c: "copy", x: "cut", v: "paste"}[key]).click();
    } else if (command) {
      return;
    } else if (event.key === " ") {
      event.preventDefault();
      el(editor.state && editor.state.playing ? "pause" : "play").click();
    } else if (key === "f") {
      fit();
    } else if (event.key === "+" || event.key === "=") {
      el("zoom-in").click();
    } else if (event.key === "-") {
      el("zoom-out").click();
    } else if (event.key === "?") {
      el("tab-help").click();
    }
  });
})();
