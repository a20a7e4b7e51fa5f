// The face editor's panel and its overlay of the face at rest (ToonFace's Editor): the server
// (toonface/studio/faces.py) makes and validates every edit; the page draws the document it sends.
"use strict";
(() => {
  const el = (id) => document.getElementById(id);
  const KINDS = ["hole", "pupil", "face", "free", "point", "feature"];
  const styleFields = studio.form(["fill", "stroke", "width", "layer", "filled", "kind", "attach"]);  // "apply-style"
  const ANGLES = new Set(["PLH", "PLV", "PRH", "PRV", "HH", "HV"]);
  const AXIS = {  // each position motor's control point and axis (toon/motors.py)
    BRL: ["BRL", "y"], BRC: ["BRC", "y"], BRM: ["BRM", "y"], BLL: ["BLL", "y"], BLC: ["BLC", "y"], BLM: ["BLM", "y"],
    ERU: ["ERU", "y"], ERL: ["ERL", "y"], ELU: ["ELU", "y"], ELL: ["ELL", "y"],
    MLH: ["ML", "x"], MLV: ["ML", "y"], MRH: ["MR", "x"], MRV: ["MR", "y"], MB: ["MB", "y"],
  };
  const faces = {doc: null, selected: 0, chosen: [0], dragging: null, waiting: false, queue: [],
                 target: "polygon"};
  window.faces = faces;  // components.js adds the component tools to it

  const node = studio.svg;

  // a drag's edits while one is in flight: an absolute move keeps only the newest, a relative one adds up
  const NEWEST = new Set(["move_component_point", "move_vertex", "move_point", "set_range"]);
  const SUMMED = new Set(["move_polygon", "move_component"]);
  const WHERE = new Set(["x", "y", "dx", "dy", "value"]);

  function merged(last, next) {
    // one message doing what `last` then `next` do, or null where they are different edits
    if (!last || last.action !== next.action) return null;
    const what = (m) => JSON.stringify(Object.entries(m).filter(([key]) => !WHERE.has(key)));
    if (what(last) !== what(next)) return null;
    if (SUMMED.has(next.action)) return {...next, dx: last.dx + next.dx, dy: last.dy + next.dy};
    return NEWEST.has(next.action) ? next : null;
  }

  function edit(message) {
    // one edit in flight; the rest wait in order, a drag's moves merged so it sends its latest position
    if (faces.waiting) {
      const last = faces.queue.length - 1;
      const both = merged(faces.queue[last], message);
      if (both) faces.queue[last] = both;
      else faces.queue.push(message);
      return;
    }
    faces.waiting = true;
    studio.send({op: "faceedit", ...message});
  }

  function settled() {
    faces.waiting = false;
    if (faces.queue.length) edit(faces.queue.shift());
  }

  faces.edit = edit;
  faces.facePoint = facePoint;

  function show(message) {
    faces.last = message;
    const before = faces.doc ? (faces.doc.components || []).length : null;
    faces.doc = message.doc;
    const after = (faces.doc.components || []).length;
    if (faces.target === "component" && before !== null && after === before + 1) {  // one made or imported: chosen
      faces.selected = after - 1;
      faces.chosen = [after - 1];
    }
    el("face-error").textContent = "";
    panel();
    draw();
  }
  faces.draw = () => draw();

  const items = () => (faces.target === "polygon" ? faces.doc.polygons : faces.doc.components || []);

  function panel() {
    const message = faces.last;
    const list = items();
    const component = faces.target === "component";
    faces.selected = Math.min(faces.selected, Math.max(0, list.length - 1));
    if (!faces.chosen.includes(faces.selected)) faces.chosen = [faces.selected];
    el("polygon").multiple = component;  // ctrl-click chooses several components, to group
    el("polygon").replaceChildren(...list.map((p, i) =>
      new Option(`${i}: ${p.name || "(unnamed)"} (${p.kind}${component ? `, layer ${p.layer ?? 1}` : ""})`, i, false,
                 component ? faces.chosen.includes(i) : i === faces.selected)));
    el("target-name").textContent = component ? "Component" : "Polygon";
    el("kind-label").hidden = component;
    el("attach-label").hidden = component;
    el("layer-label").hidden = !component;
    el("filled-label").hidden = !component;
    el("component-tools").hidden = !component;
    if (faces.componentPanel) faces.componentPanel(message);
    const spec = list[faces.selected];
    styleFields.showing(`${faces.target} ${faces.selected}`);  // a style typed and not applied stays
    const put = styleFields.put;
    if (spec) {
      put("fill", "value", (spec.color || spec.fill || "#000000").slice(0, 7));
      put("stroke", "value", (spec.stroke || "#000000").slice(0, 7));
      put("width", "value", spec.width || 0);
      if (component) {
        put("layer", "value", spec.layer ?? 1);
        const open = spec.kind === "polyline" && !spec.closed;
        put("filled", "checked", Boolean(spec.fill) && !open);
        el("filled").disabled = open;
      } else {
        put("kind", "value", spec.kind);
        put("attach", "value", spec.attach || "");
      }
    }
    if (document.activeElement !== el("face-name")) el("face-name").value = faces.doc.name;
    angles();
    el("face-undo").disabled = message.undo === 0;
    el("face-redo").disabled = message.redo === 0;
  }

  function angles() {
    // the angle motors' ranges in degrees (ToonFace: "for the eyes and head"), edited as numbers
    const rows = [...ANGLES].map((code) => {
      const [lo, hi] = faces.doc.motors[code];
      const row = document.createElement("label");
      const input = (end, value) => {
        const box = Object.assign(document.createElement("input"), {type: "number", step: "1", value});
        box.id = `angle-${code}-${end}`;
        box.addEventListener("change", () => edit({action: "set_range", code, end, value: Number(box.value)}));
        return box;
      };
      row.append(`${code} `, input("min", lo), " to ", input("max", hi), "°");
      return row;
    });
    el("angles").replaceChildren(...rows);
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
    const chosen = items()[faces.selected];
    if (chosen && faces.target === "component" && faces.componentParts) parts.push(...faces.componentParts(r));
    const spec = faces.target === "polygon" ? chosen : null;
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

  const PICK_PIXELS = 14;  // a handle this near the pointer is taken, the nearest of several

  function nearestHandle(event) {
    // the handle (vertex, point, range end) nearest the pointer on screen, within PICK_PIXELS
    let best = null;
    let bestDistance = PICK_PIXELS;
    for (const handle of el("shape").querySelectorAll("[data-drag]:not([data-drag=unit])")) {
      const box = handle.getBoundingClientRect();
      const d = Math.hypot(event.clientX - (box.left + box.width / 2), event.clientY - (box.top + box.height / 2));
      if (d < bestDistance) [best, bestDistance] = [handle, d];
    }
    return best;
  }

  function hover(event) {
    // the handle a press would take shows strong, the others faint
    if (faces.dragging) return;
    const near = nearestHandle(event);
    for (const handle of el("shape").querySelectorAll(".near")) if (handle !== near) handle.classList.remove("near");
    if (near) near.classList.add("near");
    el("shape").classList.toggle("picking", near !== null);
  }

  function down(event) {
    const target = nearestHandle(event) || event.target;  // the nearest wins, not the one drawn on top
    if (!target.dataset || !target.dataset.drag || event.button !== 0) return;
    faces.dragging = {...target.dataset};
    if (target.dataset.drag === "cpoint" && faces.choosePoint) faces.choosePoint(target.dataset);
    if ((target.dataset.drag === "vertex" || target.dataset.drag === "cpoint") && event.shiftKey
        || target.dataset.drag === "unit") {
      faces.dragging = {drag: faces.target, from: facePoint(event)};  // shift: the whole polygon or component
    }
    el("shape").setPointerCapture(event.pointerId);
    event.preventDefault();
  }

  const SNAP_PIXELS = 8;  // a dragged point lands on another handle this near (Ctrl: no snapping)

  function same(handle, drag) {
    // whether a handle is the one being dragged (redrawn after every edit, so told by its data)
    const d = handle.dataset;
    return d.drag === drag.drag && d.index === drag.index && d.part === drag.part && d.name === drag.name;
  }

  function snapped(event, drag) {
    // the pointer in face units, or the centre of the other handle (a control point, a vertex) it is near
    const free = facePoint(event);
    if (event.ctrlKey || event.metaKey) return [free, false];
    let best = null;
    let bestDistance = SNAP_PIXELS;
    for (const handle of el("shape").querySelectorAll("[data-drag]:not([data-drag=unit]):not([data-drag=range])")) {
      if (same(handle, drag)) continue;
      const box = handle.getBoundingClientRect();
      const [cx, cy] = [box.left + box.width / 2, box.top + box.height / 2];
      const d = Math.hypot(event.clientX - cx, event.clientY - cy);
      if (d < bestDistance) [best, bestDistance] = [{clientX: cx, clientY: cy}, d];
    }
    return best ? [facePoint(best), true] : [free, false];
  }

  function move(event) {
    const drag = faces.dragging;
    if (!drag) return;
    const pointish = drag.drag === "vertex" || drag.drag === "cpoint" || drag.drag === "point";
    const [[x, y], snap] = pointish ? snapped(event, drag) : [facePoint(event), false];
    faces.snapped = snap;
    if (drag.drag === "polygon" || drag.drag === "component") {
      const [dx, dy] = [x - drag.from[0], y - drag.from[1]];
      drag.from = [x, y];
      edit({action: `move_${drag.drag}`, [drag.drag]: faces.selected, dx, dy});
    } else if (drag.drag === "cpoint") {
      if (drag.master) return;  // a master point sits on its control point: drag that instead
      edit({action: "move_component_point", component: faces.selected, index: Number(drag.index), x, y,
            part: drag.part});
    } else if (drag.drag === "vertex") {
      edit({action: "move_vertex", polygon: faces.selected, index: Number(drag.index), x, y});
    } else if (drag.drag === "point") {
      edit({action: "move_point", name: drag.name, x, y});
    } else if (drag.drag === "range") {
      edit({action: "set_range", code: drag.code, end: drag.end, value: drag.axis === "x" ? x : y});
    }
  }

  function nearestSide(v, x, y, closed = true) {
    // the side of outline v ([[x, y], ...]) nearest (x, y): the index of its first point
    let best = 0;
    let bestDistance = Infinity;
    v.forEach(([ax, ay], i) => {
      if (!closed && i === v.length - 1) return;
      const [bx, by] = v[(i + 1) % v.length];
      const [dx, dy] = [bx - ax, by - ay];
      const t = Math.max(0, Math.min(1, ((x - ax) * dx + (y - ay) * dy) / (dx * dx + dy * dy || 1)));
      const distance = Math.hypot(ax + t * dx - x, ay + t * dy - y);
      if (distance < bestDistance) [best, bestDistance] = [i, distance];
    });
    return best;
  }
  faces.nearestSide = nearestSide;

  function addVertex(event) {
    // a double-click on the chosen item's outline: a point there, after the nearer end of that side
    if (event.target.getAttribute("class") !== "outline-hit") return;
    const [x, y] = facePoint(event);
    if (faces.target === "component") {
      if (faces.addPoint) faces.addPoint(x, y);
      return;
    }
    const spec = faces.doc && faces.doc.polygons[faces.selected];
    if (spec) edit({action: "add_vertex", polygon: faces.selected, after: nearestSide(spec.vertices, x, y), x, y});
  }

  function deleteVertex(event) {
    const drag = event.target.dataset && event.target.dataset.drag;
    if (drag === "cpoint") {
      event.preventDefault();
      edit({action: "delete_component_point", component: faces.selected, part: event.target.dataset.part,
            index: Number(event.target.dataset.index)});
      return;
    }
    if (drag !== "vertex") return;
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
    const chosen = [...event.target.selectedOptions].map((option) => Number(option.value));
    const added = chosen.find((i) => !faces.chosen.includes(i));  // the one just clicked is the one edited
    faces.selected = added !== undefined ? added : Number(event.target.value);
    faces.chosen = chosen;
    panel();
    draw();
  });
  el("shape").addEventListener("pointerdown", down);
  el("shape").addEventListener("dblclick", addVertex);
  el("shape").addEventListener("contextmenu", deleteVertex);
  el("shape").addEventListener("pointermove", move);
  el("shape").addEventListener("pointermove", hover);
  el("shape").addEventListener("pointerup", () => { faces.dragging = null; });
  el("apply-style").addEventListener("click", () => {
    const style = {stroke: el("stroke").value, width: Number(el("width").value)};
    if (faces.target === "component") {
      edit({action: "set_component", component: faces.selected,
            fields: {...style, fill: el("filled").checked ? el("fill").value : null,
                     layer: Number(el("layer").value)}});
    } else {
      edit({action: "set_style", polygon: faces.selected, fields: {...style, color: el("fill").value,
                                                                   kind: el("kind").value,
                                                                   attach: el("attach").value || null}});
    }
    styleFields.applied();
  });
  // the buttons act on the chosen polygon or component, as a unit
  const whole = (verb, extra = {}) => () => edit({action: `${verb}_${faces.target}`, [faces.target]: faces.selected,
                                                  ...extra});
  el("add-polygon").addEventListener("click", () => {
    const [x0, y0, x1, y1] = faces.doc.viewbox;
    faces.target = "polygon";
    el("target-polygon").checked = true;
    faces.selected = faces.doc.polygons.length;  // the new one, drawn last
    edit({action: "add_polygon", x: (x0 + x1) / 2, y: (y0 + y1) / 2});
  });
  el("duplicate").addEventListener("click", whole("duplicate", {dx: 10, dy: 0}));
  el("copy-item").addEventListener("click", () => edit({action: "copy", kind: faces.target, index: faces.selected}));
  el("paste-item").addEventListener("click", () => {
    faces.selected = items().length;  // the pasted one, drawn last
    edit({action: "paste"});
  });
  el("delete-polygon").addEventListener("click", whole("delete"));
  el("flip-x").addEventListener("click", whole("flip", {axis: "x"}));
  el("flip-y").addEventListener("click", whole("flip", {axis: "y"}));
  el("grow").addEventListener("click", whole("scale", {factor: 1.1}));
  el("shrink").addEventListener("click", whole("scale", {factor: 0.9}));
  function choose(target, index) {
    faces.target = target;
    el(`target-${target}`).checked = true;
    faces.selected = index;
    faces.chosen = [index];
    panel();
    draw();
  }
  faces.choose = choose;
  for (const target of ["polygon", "component"]) el(`target-${target}`).addEventListener("change", () => choose(target, 0));
  el("face-undo").addEventListener("click", () => edit({action: "undo"}));
  el("face-redo").addEventListener("click", () => edit({action: "redo"}));
  el("face-name").addEventListener("change", (event) => edit({action: "rename", name: event.target.value}));
  el("face-save").addEventListener("click", () => edit({action: "save", path: el("face-path").value}));
  studio.handlers.face = show;
  // this page's edit was done (every page gets the face it made, so the face alone does not say whose)
  studio.handlers.answered = (message) => {
    if (message.op === "faceedit") settled();
  };
  studio.onError = (message, op) => {  // a refused edit: said next to the face panel too, and the next one may go
    if (faces.waiting && op === "faceedit") {
      el("face-error").textContent = message;
      const named = /(polygons|components)\[(\d+)\]/.exec(message);  // the validator names the offending item
      if (named) choose(named[1] === "polygons" ? "polygon" : "component", Number(named[2]));
      settled();
    }
  };
  const drawn = studio.onFrame;
  studio.onFrame = (frame) => {
    if (drawn) drawn(frame);
    if (!el("shape").classList.contains("off")) draw();  // the face view was redrawn: keep the overlay on its viewBox
  };
})();
