// The face editor's panel and its overlay of the face at rest (ToonFace's Editor): the server
// (toonface/studio/faces.py) makes and validates every edit; the page draws the document it sends.
"use strict";
(() => {
  const NS = "http://www.w3.org/2000/svg";
  const el = (id) => document.getElementById(id);
  const KINDS = ["hole", "pupil", "face", "free", "point", "feature"];
  const ANGLES = new Set(["PLH", "PLV", "PRH", "PRV", "HH", "HV"]);
  const AXIS = {  // each position motor's control point and axis (toon/motors.py)
    BRL: ["BRL", "y"], BRC: ["BRC", "y"], BRM: ["BRM", "y"], BLL: ["BLL", "y"], BLC: ["BLC", "y"], BLM: ["BLM", "y"],
    ERU: ["ERU", "y"], ERL: ["ERL", "y"], ELU: ["ELU", "y"], ELL: ["ELL", "y"],
    MLH: ["ML", "x"], MLV: ["ML", "y"], MRH: ["MR", "x"], MRV: ["MR", "y"], MB: ["MB", "y"],
  };
  const faces = {doc: null, selected: 0, dragging: null, waiting: false, pending: null};
  window.faces = faces;

  function node(name, attrs) {
    const n = document.createElementNS(NS, name);
    for (const [key, value] of Object.entries(attrs)) n.setAttribute(key, value);
    return n;
  }

  function edit(message) {
    // one edit in flight: a drag sends its latest position when the previous edit has come back
    if (faces.waiting) {
      faces.pending = message;
      return;
    }
    faces.waiting = true;
    studio.send({op: "faceedit", ...message});
  }

  function settled() {
    faces.waiting = false;
    if (faces.pending) {
      const next = faces.pending;
      faces.pending = null;
      edit(next);
    }
  }

  function show(message) {
    faces.last = message;
    faces.doc = message.doc;
    el("face-error").textContent = "";
    panel();
    settled();
    draw();
  }

  function panel() {
    const message = faces.last;
    const polygons = faces.doc.polygons;
    faces.selected = Math.min(faces.selected, Math.max(0, polygons.length - 1));
    el("polygon").replaceChildren(...polygons.map((p, i) =>
      new Option(`${i}: ${p.name || "(unnamed)"} (${p.kind})`, i, false, i === faces.selected)));
    const spec = polygons[faces.selected];
    if (spec) {
      el("fill").value = spec.color.slice(0, 7);
      el("stroke").value = (spec.stroke || "#000000").slice(0, 7);
      el("width").value = spec.width || 0;
      el("kind").value = spec.kind;
    }
    if (document.activeElement !== el("face-name")) el("face-name").value = faces.doc.name;
    el("face-undo").disabled = message.undo === 0;
    el("face-redo").disabled = message.redo === 0;
  }

  function draw() {
    const shape = el("shape");
    const face = el("view").firstElementChild;
    if (!faces.doc || !face) return;
    shape.setAttribute("viewBox", face.getAttribute("viewBox"));
    shape.setAttribute("preserveAspectRatio", face.getAttribute("preserveAspectRatio"));
    const box = face.viewBox.baseVal;
    const r = Math.max(box.width, box.height) / 110;
    const parts = [];  // the chosen polygon last, on top of the control points
    for (const [code, [point, axis]] of Object.entries(AXIS)) {
      const [px, py] = faces.doc.points[point];
      const [lo, hi] = faces.doc.motors[code];
      const at = (v) => (axis === "x" ? [v, -py] : [px, -v]);
      parts.push(node("line", {class: "range", x1: at(lo)[0], y1: at(lo)[1], x2: at(hi)[0], y2: at(hi)[1],
                               "stroke-width": r / 3}));
      for (const [end, v] of [["min", lo], ["max", hi]]) {
        const [x, y] = at(v);
        parts.push(node("rect", {class: `range-end ${axis}`, x: x - r * 0.7, y: y - r * 0.7, width: 1.4 * r,
                                 height: 1.4 * r, "stroke-width": r / 4, "data-drag": "range", "data-code": code,
                                 "data-end": end, "data-axis": axis}));
      }
    }
    for (const [name, [x, y]] of Object.entries(faces.doc.points)) {
      parts.push(node("circle", {class: "rest-point", cx: x, cy: -y, r, "stroke-width": r / 4,
                                 "data-drag": "point", "data-name": name}));
    }
    const spec = faces.doc.polygons[faces.selected];
    if (spec) {
      const points = spec.vertices.map(([x, y]) => `${x},${-y}`).join(" ");
      parts.push(node("polygon", {class: "outline", points, "stroke-width": r / 3}));
      parts.push(node("polygon", {class: "outline-hit", points, "stroke-width": 3 * r}));  // an easy target
      spec.vertices.forEach(([x, y], index) => parts.push(node("rect", {
        class: "vertex", x: x - r, y: -y - r, width: 2 * r, height: 2 * r, "stroke-width": r / 3,
        "data-drag": "vertex", "data-index": index})));
    }
    shape.replaceChildren(...parts);
  }

  function facePoint(event) {
    const p = new DOMPoint(event.clientX, event.clientY).matrixTransform(el("shape").getScreenCTM().inverse());
    return [p.x, -p.y];  // face units: y up
  }

  function down(event) {
    const target = event.target;
    if (!target.dataset || !target.dataset.drag || event.button !== 0) return;
    faces.dragging = {...target.dataset};
    if (target.dataset.drag === "vertex" && event.shiftKey) {  // shift: the whole polygon, as a unit
      faces.dragging = {drag: "polygon", from: facePoint(event)};
    }
    el("shape").setPointerCapture(event.pointerId);
    event.preventDefault();
  }

  function move(event) {
    const drag = faces.dragging;
    if (!drag) return;
    const [x, y] = facePoint(event);
    if (drag.drag === "polygon") {
      const [dx, dy] = [x - drag.from[0], y - drag.from[1]];
      drag.from = [x, y];
      edit({action: "move_polygon", polygon: faces.selected, dx, dy});
    } else if (drag.drag === "vertex") {
      edit({action: "move_vertex", polygon: faces.selected, index: Number(drag.index), x, y});
    } else if (drag.drag === "point") {
      edit({action: "move_point", name: drag.name, x, y});
    } else if (drag.drag === "range") {
      edit({action: "set_range", code: drag.code, end: drag.end, value: drag.axis === "x" ? x : y});
    }
  }

  function addVertex(event) {
    // a double-click on the chosen polygon's outline: a vertex there, after the nearer end of that side
    const spec = faces.doc && faces.doc.polygons[faces.selected];
    if (!spec || event.target.getAttribute("class") !== "outline-hit") return;
    const [x, y] = facePoint(event);
    const v = spec.vertices;
    let best = 0;
    let bestDistance = Infinity;
    v.forEach(([ax, ay], i) => {
      const [bx, by] = v[(i + 1) % v.length];
      const [dx, dy] = [bx - ax, by - ay];
      const t = Math.max(0, Math.min(1, ((x - ax) * dx + (y - ay) * dy) / (dx * dx + dy * dy || 1)));
      const distance = Math.hypot(ax + t * dx - x, ay + t * dy - y);
      if (distance < bestDistance) [best, bestDistance] = [i, distance];
    });
    edit({action: "add_vertex", polygon: faces.selected, after: best, x, y});
  }

  function deleteVertex(event) {
    if (!event.target.dataset || event.target.dataset.drag !== "vertex") return;
    event.preventDefault();
    edit({action: "delete_vertex", polygon: faces.selected, index: Number(event.target.dataset.index)});
  }

  function setDesign(on) {
    el("shape").classList.toggle("off", !on);
    el("handles").classList.toggle("hidden", on || !el("show-points").checked);
    draw();
  }

  el("kind").replaceChildren(...KINDS.map((k) => new Option(k, k)));
  el("design").addEventListener("change", (event) => setDesign(event.target.checked));
  el("polygon").addEventListener("change", (event) => {
    faces.selected = Number(event.target.value);
    panel();
    draw();
  });
  el("shape").addEventListener("pointerdown", down);
  el("shape").addEventListener("dblclick", addVertex);
  el("shape").addEventListener("contextmenu", deleteVertex);
  el("shape").addEventListener("pointermove", move);
  el("shape").addEventListener("pointerup", () => { faces.dragging = null; });
  el("apply-style").addEventListener("click", () => edit({action: "set_style", polygon: faces.selected, fields: {
    color: el("fill").value, stroke: el("stroke").value, width: Number(el("width").value), kind: el("kind").value}}));
  const whole = (action, extra = {}) => () => edit({action, polygon: faces.selected, ...extra});
  el("duplicate").addEventListener("click", whole("duplicate_polygon", {dx: 10, dy: 0}));
  el("delete-polygon").addEventListener("click", whole("delete_polygon"));
  el("flip-x").addEventListener("click", whole("flip_polygon", {axis: "x"}));
  el("flip-y").addEventListener("click", whole("flip_polygon", {axis: "y"}));
  el("grow").addEventListener("click", whole("scale_polygon", {factor: 1.1}));
  el("shrink").addEventListener("click", whole("scale_polygon", {factor: 0.9}));
  el("face-undo").addEventListener("click", () => edit({action: "undo"}));
  el("face-redo").addEventListener("click", () => edit({action: "redo"}));
  el("face-name").addEventListener("change", (event) => edit({action: "rename", name: event.target.value}));
  el("face-save").addEventListener("click", () => edit({action: "save", path: el("face-path").value}));
  studio.handlers.face = show;
  studio.onError = (message) => {  // a refused edit: said next to the face panel too, and the next one may go
    if (faces.waiting) {
      el("face-error").textContent = message;
      settled();
    }
  };
  const drawn = studio.onFrame;
  studio.onFrame = (frame) => {
    if (drawn) drawn(frame);
    if (!el("shape").classList.contains("off")) draw();  // the face view was redrawn: keep the overlay on its viewBox
  };
})();
