// The studio page: a view of the server's session (toonface/studio/session.py). It draws the
// frames the server sends and sends back what the user does; it computes no geometry itself.
(() => {
"use strict";
  const studio = {
    socket: null,
    frames: 0,          // frames drawn since the page opened (tests read it)
    received: 0,        // frames the server sent; a loaded page draws only the newest of those waiting
    rate: 0,            // frames drawn in the last second
    last: null,         // the last frame
    dragging: null,     // the control point being dragged
  };
  window.studio = studio;
  studio.send = send;  // editor.js sends through the same socket
  studio.handlers = {};  // more message types, by the other scripts

  const $ = (id) => document.getElementById(id);
  const drawing = new toonDraw.Drawing($("view"));
  const SVG = "http://www.w3.org/2000/svg";

  studio.svg = (name, attrs = {}) => {
    // an SVG element with these attributes (the other scripts draw with it too)
    const node = document.createElementNS(SVG, name);
    for (const [key, value] of Object.entries(attrs)) node.setAttribute(key, value);
    return node;
  };

  studio.form = (ids) => {
    // fields a panel redraws from each message the server sends, applied by a button: one the user
    // typed in keeps what was typed until it is applied (or the panel shows another thing), so that
    // a message answering an earlier action, coming while the user types, does not undo the typing
    const typed = new Set();
    let shown = null;
    // "input" comes with each key; a pick in a list may come as a "change" alone
    for (const id of ids) {
      for (const kind of ["input", "change"]) $(id).addEventListener(kind, () => typed.add(id));
    }
    return {
      showing(key) {  // whose values the fields show now: another's drops what was typed
        if (key !== shown) typed.clear();
        shown = key;
      },
      put(id, field, value) {
        if (!typed.has(id)) $(id)[field] = value;
      },
      applied() {  // sent: the next message shows what the fields hold
        typed.clear();
      },
    };
  };

  function send(message) {
    if (studio.socket && studio.socket.readyState === WebSocket.OPEN) {
      studio.socket.send(JSON.stringify(message));
    }
  }

  function connect() {
    const socket = new WebSocket(`ws://${location.host}/ws`);
    studio.socket = socket;
    socket.onmessage = (event) => {
      const message = JSON.parse(event.data);
      if (message.type === "frame") {
        // one frame drawn between two paints, the rest wait and the newest is drawn at the paint: on a
        // loaded machine frames queued behind slow draws, and the page showed (and paused at) a time
        // the server had left a second before
        studio.received += 1;
        if (drawnSincePaint) {
          pending = message;
          return;
        }
        drawnSincePaint = true;
        requestAnimationFrame(() => {
          drawnSincePaint = false;
          drawPending();
        });
        draw(message);
        return;
      }
      drawPending();  // what came before this message is shown before it is taken
      if (message.type === "hello") {
        describe(message);
        if (studio.onHello) studio.onHello(message);
      }
      else if (message.type === "animation" && studio.onAnimation) studio.onAnimation(message);
    else if (studio.handlers[message.type]) studio.handlers[message.type](message);
      else if (message.type === "error") {
      say(`error: ${message.message}`, true);
      if (studio.onError) studio.onError(message.message, message.op);
    }
    else if (message.type === "said") say(message.message, false);
    else if (message.type === "quality") quality(message);
    };
    socket.onclose = () => {
      $("status").textContent = "disconnected: reconnecting…";
      setTimeout(connect, 1000);
    };
  }

  function quality(q) {
    const latency = q.latency_ms === null ? "–" : `${q.latency_ms} ms`;
    $("quality").textContent = `latency ${latency} · loss ${q.loss_pct} % · concealed ${q.concealed_pct} % · `
      + `${q.packets} packets` + (q.diagnosis ? ` · ${q.diagnosis}` : "");
    studio.quality = q;
  }

  function describe(hello) {
    $("live").hidden = !hello.live;
    $("live-name").textContent = hello.live || "";
    const faces = $("face");
    const names = hello.faces.includes(hello.face) ? hello.faces : [...hello.faces, hello.face];  // a face file too
    faces.replaceChildren(...names.map((name) => new Option(name, name, false, name === hello.face)));
    $("expressions").replaceChildren(...hello.expressions.map((name) => button(name, "play")));
    $("motions").replaceChildren(...hello.motions.map((name) => button(name, "play")));
    const groups = hello.groups.map((group) => {
      const set = document.createElement("fieldset");
      const legend = document.createElement("legend");
      legend.textContent = group.title;
      set.append(legend, ...group.motors.map(slider));
      return set;
    });
    $("sliders").replaceChildren(...groups);
  }

  function say(text, bad) {
    const line = $("message");
    line.textContent = text;
    line.title = text;  // one line in the header; the whole of it on hover
    line.classList.toggle("bad", bad);
  }
  studio.say = say;

  function button(name, op) {
    const b = document.createElement("button");
    b.type = "button";
    b.textContent = name;
    b.dataset.name = name;
    b.addEventListener("click", () => send({op, name, loop: op === "play" && $("loop-expression").checked}));
    return b;
  }

  function slider(motor) {
    const row = document.createElement("label");
    row.className = "motor";
    row.title = motor.description;
    const code = document.createElement("span");  // what a designer calls it, and its code
    code.className = "name";
    code.append(motor.name || motor.code);
    if (motor.name && motor.name !== motor.code) code.append(Object.assign(document.createElement("small"), {textContent: motor.code}));
    const input = document.createElement("input");
    Object.assign(input, {type: "range", min: 0, max: 1, step: 0.001, id: `motor-${motor.code}`});
    input.setAttribute("aria-label", motor.description);
    const value = document.createElement("output");
    value.id = `value-${motor.code}`;
    input.addEventListener("input", () => send({op: "motor", code: motor.code, value: Number(input.value)}));
    row.append(code, input, value);
    return row;
  }

  let pending = null;  // the newest frame not drawn yet
  let drawnSincePaint = false;
  function drawPending() {
    if (pending === null) return;
    const frame = pending;
    pending = null;
    draw(frame);
  }

  function draw(frame) {
    const face = drawing.show(frame);
    const handles = $("handles");
    handles.setAttribute("viewBox", face.getAttribute("viewBox"));
    handles.setAttribute("preserveAspectRatio", face.getAttribute("preserveAspectRatio"));
    const box = face.viewBox.baseVal;
    const radius = Math.max(box.width, box.height) / 90;
    for (const [name, [x, y]] of Object.entries(frame.points)) {
      let dot = handles.querySelector(`circle[data-point="${name}"]`);
      if (!dot) {
        dot = studio.svg("circle");
        dot.dataset.point = name;
        dot.addEventListener("pointerdown", startDrag);
        handles.append(dot);
      }
      dot.setAttribute("cx", x);
      dot.setAttribute("cy", y);
      dot.setAttribute("r", radius);
      dot.setAttribute("stroke-width", radius / 4);
    }
    for (const [code, value] of Object.entries(frame.values)) {
      const input = $(`motor-${code}`);
      if (input && document.activeElement !== input) input.value = value;
      const shown = $(`value-${code}`);
      if (shown) shown.textContent = value.toFixed(2);
    }
    if (document.activeElement !== $("show-live")) $("show-live").checked = frame.showing === "live";
    studio.last = frame;
    studio.frames += 1;
    countFrame();
    if (studio.onFrame) studio.onFrame(frame);
  }

  const drawnAt = [];
  function countFrame() {
    const now = performance.now();
    drawnAt.push(now);
    while (drawnAt.length && drawnAt[0] < now - 1000) drawnAt.shift();
    studio.rate = drawnAt.length;
    // the server sends a frame when the face changes: a still face is not a slow one
    $("status").textContent = studio.rate > 1 ? `moving · ${studio.rate} frames/s` : "still";
  }

  function toFace(event) {
    const matrix = $("handles").getScreenCTM().inverse();
    const point = new DOMPoint(event.clientX, event.clientY).matrixTransform(matrix);
    return [point.x, point.y];
  }

  function startDrag(event) {
    const dot = event.currentTarget;
    studio.dragging = dot.dataset.point;
    dot.classList.add("dragging");
    dot.setPointerCapture(event.pointerId);
    dot.addEventListener("pointermove", moveDrag);
    dot.addEventListener("pointerup", endDrag, {once: true});
    event.preventDefault();
  }

  function moveDrag(event) {
    const [x, y] = toFace(event);
    send({op: "drag", point: studio.dragging, x, y});
  }

  function endDrag(event) {
    const dot = event.currentTarget;
    dot.classList.remove("dragging");
    dot.removeEventListener("pointermove", moveDrag);
    studio.dragging = null;
  }

  function follow(event) {
    // the pointer about the face (not the stage, which is wider or taller than the face it shows): -1..1
    if (!$("follow").checked || studio.dragging || !$("handles").viewBox.baseVal) return;
    const box = $("handles").viewBox.baseVal;
    const [fx, fy] = toFace(event);
    const x = Math.max(-1, Math.min(1, ((fx - box.x) / box.width) * 2 - 1));
    const y = Math.max(-1, Math.min(1, ((fy - box.y) / box.height) * 2 - 1));
    send({op: "look", x, y});
  }

  function showTab(tab) {
    // one panel beside the face: Test (its sliders), the Face editor, the Mapping tuner or the Keys
    for (const other of document.querySelectorAll("#tabs [role=tab]")) {
      const chosen = other === tab;
      other.setAttribute("aria-selected", String(chosen));
      const panel = $(other.dataset.panel);
      if (panel.tagName === "DETAILS") panel.open = chosen;
      else panel.hidden = !chosen;
    }
  }
  for (const tab of document.querySelectorAll("#tabs [role=tab]")) tab.addEventListener("click", () => showTab(tab));

  $("show-live").addEventListener("change", (event) => send({op: "live", on: event.target.checked}));
  $("face").addEventListener("change", (event) => send({op: "face", name: event.target.value}));
  $("reset").addEventListener("click", () => send({op: "reset"}));
  $("follow").addEventListener("change", (event) => send({op: "follow", on: event.target.checked}));
  $("show-points").addEventListener("change", (event) => $("handles").classList.toggle("hidden", !event.target.checked));
  $("stage").addEventListener("pointermove", follow);
  // the socket opens once every script has loaded: a message that came while a later script was
  // still downloading would find none of its handlers (the face editor's lists stayed empty)
  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", connect);
  else connect();
})();
