// The face editor's CharToon component tools (CharToon's Face Editor): new components, their points
// chosen and re-kinded, smooth ranges and invisible segments, animated parameters, groups and the
// component library. The server (toonface/studio/component_edits.py) makes and checks every edit.
"use strict";
(() => {
  const el = (id) => document.getElementById(id);
  const faces = window.faces;
  const node = studio.svg;
  const tools = {point: null};  // the chosen point: {part, index}
  const outlineFields = studio.form(["smooth", "hidden-segments", "closed", "coupling", "clip"]);  // "apply-outline"
  const pointKindFields = studio.form(["point-kind", "point-master"]);  // "set-point"
  const chosen = () => (faces.doc.components || [])[faces.selected];
  const outlinePart = (spec) => (spec.kind === "skeleton" ? "body" : "points");
  const closed = (spec) => spec.kind === "polygon" || spec.kind === "ellipse" || spec.kind === "image" || spec.closed
    || (spec.kind === "skeleton" && spec.closed !== false);
  const PARTS = ["points", "skeleton", "body"];
  // the mean of points [[x, y], ...]: a composite's handle, a scale's origin
  const centre = (points) => [0, 1].map((k) => points.reduce((s, p) => s + p[k], 0) / Math.max(points.length, 1));

  function pointKind(ref) {
    if (typeof ref === "string") return ["master", ref];
    if (Array.isArray(ref)) return ["frozen", ""];
    if (!("slave" in ref)) return ["fixed", ""];
    if (typeof ref.slave === "string") return ["slave", ref.slave];
    // a slave of several masters: its heaviest first, each with its share ("MB 75% ML 25%")
    const shares = Object.entries(ref.slave).sort((a, b) => b[1] - a[1]);
    return ["slave", shares[0][0], shares.map(([name, w]) => `${name} ${Math.round(w * 100)}%`).join(" ")];
  }

  function options(select, values, value, labels = values) {
    select.replaceChildren(...values.map((v, i) => new Option(labels[i], v, false, v === value)));
  }

  faces.componentPanel = (message) => {
    el("libraries").replaceChildren(...message.libraries.map((name) => new Option(name, name)));
    const listed = message.listed || {};
    options(el("library-entry"), listed.names || [], el("library-entry").value);
    const points = Object.keys(faces.doc.points);
    options(el("point-master"), ["", ...points], el("point-master").value, ["(nearest)", ...points]);
    const drivers = [...Object.keys(faces.doc.motors), ...(faces.doc.head && faces.doc.head.tilt ? ["HT"] : []),
      ...Object.keys(faces.doc.params || {})];  // the 21 and the face's parameters
    options(el("param-motor"), drivers, el("param-motor").value || "MB");
    const spec = chosen();
    const basic = spec && spec.kind !== "composite";
    for (const id of ["outline-fields", "animate-fields"]) el(id).hidden = !basic;
    el("cpoint").disabled = !basic;
    if (!basic) {
      el("cpoint").replaceChildren();
      return;
    }
    const refs = PARTS.flatMap((part) => (spec[part] || []).map((ref, index) => [part, index, ref]));
    const values = refs.map(([part, index]) => `${part}:${index}`);
    const labels = refs.map(([part, index, ref]) => {
      const [kind, master, shares] = pointKind(ref);
      return `${part}[${index}] ${kind} ${shares || master}`.trim();
    });
    const current = tools.point ? `${tools.point.part}:${tools.point.index}` : values[0];
    options(el("cpoint"), values, values.includes(current) ? current : values[0], labels);
    pointFields();
    const smooth = spec.smooth === true ? "all" : (spec.smooth || []).map(([a, b]) => `${a}-${b}`).join(", ");
    outlineFields.showing(`${faces.target} ${faces.selected}`);  // what was typed and not applied stays
    outlineFields.put("smooth", "value", smooth);
    outlineFields.put("hidden-segments", "value", (spec.hidden || []).join(", "));
    outlineFields.put("closed", "checked", closed(spec));
    el("closed").disabled = spec.kind === "polygon" || spec.kind === "ellipse";
    el("coupling-label").hidden = spec.kind !== "skeleton";
    outlineFields.put("coupling", "value", spec.coupling || "edge");
    outlineFields.put("clip", "value", spec.clip || "");
    const params = ["visible", "translate", "scale"].filter((key) => spec[key]).map((key) => {
      const p = spec[key];
      return key === "visible" ? `visible by ${p.motor} in [${p.range}]`
        : `${key} by ${p.motor} ${JSON.stringify(p.at0)}→${JSON.stringify(p.at1)}`;
    });
    el("params").textContent = params.join("; ");
  };

  function pointFields() {
    // the chosen point's kind and master, in the point row
    const [part, index] = (el("cpoint").value || "points:0").split(":");
    tools.point = {part, index: Number(index)};
    const ref = (chosen()[part] || [])[Number(index)];
    if (ref === undefined) return;
    const [kind, master] = pointKind(ref);
    pointKindFields.showing(`${faces.target} ${faces.selected} ${part}:${index}`);  // picked and not set: it stays
    pointKindFields.put("point-kind", "value", kind);
    pointKindFields.put("point-master", "value", master);
  }

  faces.choosePoint = (data) => {
    el("cpoint").value = `${data.part}:${data.index}`;
    pointFields();
    faces.draw();
  };

  faces.componentParts = (r) => {
    // the chosen component's outlines at rest, its points (diamonds; masters as rings on their control
    // point) numbered, and for a composite a handle to drag it as a unit
    const spec = chosen();
    const lines = (faces.last.outlines || [])[faces.selected] || [];
    const parts = [];
    const flat = (line) => line.map(([x, y]) => `${x},${-y}`).join(" ");
    const ring = (line, i) => (i === 0 && spec.kind !== "composite" && closed(spec) ? [...line, line[0]] : line);
    lines.forEach((line, i) => parts.push(node("polyline", {class: "outline", points: flat(ring(line, i)),
                                                                   "stroke-width": r / 3, "stroke-opacity": i ? 0.5 : 1})));
    if (spec.kind === "composite") {
      const all = lines.flat();
      if (all.length) {
        const [cx, cy] = centre(all);
        parts.push(node("rect", {class: "unit", x: cx - 1.5 * r, y: -cy - 1.5 * r, width: 3 * r, height: 3 * r,
                                       "stroke-width": r / 3, "data-drag": "unit"}));
      }
      return parts;
    }
    const outline = lines[0] || [];
    parts.push(node("polyline", {class: "outline-hit", points: flat(ring(outline, 0)), "stroke-width": 3 * r}));
    for (const part of PARTS) {
      (spec[part] || []).forEach((ref, index) => {
        const [kind, master] = pointKind(ref);
        const [x, y] = kind === "master" ? faces.doc.points[master] : Array.isArray(ref) ? ref : (ref.at || ref.fixed);
        const picked = tools.point && tools.point.part === part && tools.point.index === index;
        const data = {"data-drag": "cpoint", "data-part": part, "data-index": index, "stroke-width": r / 3};
        if (kind === "master") {
          parts.push(node("circle", {class: `vertex master${picked ? " chosen" : ""}`, cx: x, cy: -y,
                                           r: 1.4 * r, "data-master": master, ...data}));
        } else {
          parts.push(node("rect", {class: `vertex${picked ? " chosen" : ""}`, x: x - r, y: -y - r, width: 2 * r,
                                         height: 2 * r, transform: `rotate(45 ${x} ${-y})`, ...data}));
        }
        const label = node("text", {class: "index", x: x + 1.6 * r, y: -y - 1.2 * r, "font-size": 2.2 * r});
        label.textContent = part === "points" ? `${index}` : `${part[0]}${index}`;
        parts.push(label);
      });
    }
    return parts;
  };

  faces.addPoint = (x, y) => {
    const spec = chosen();
    if (!spec || spec.kind === "composite") return;
    const outline = ((faces.last.outlines || [])[faces.selected] || [])[0];
    const after = faces.nearestSide(outline, x, y, closed(spec));
    faces.edit({action: "add_component_point", component: faces.selected, part: outlinePart(spec), after, x, y});
  };

  function ranges(text) {
    // "0-3, 5-7" as [[0, 3], [5, 7]]; "all" as true; nothing as null (none)
    const t = text.trim();
    if (!t) return null;
    if (t === "all") return true;
    return t.split(",").map((range) => range.split("-").map((n) => Number(n.trim())));
  }

  const numbers = (text) => text.trim().split(/[\s,]+/).filter(Boolean).map(Number);

  function param() {
    // the parameter row as a field: visible low high; translate dx0 dy0 dx1 dy1; scale sx0 sy0 sx1 sy1
    const key = el("param").value;
    const motor = el("param-motor").value;
    const v = numbers(el("param-values").value);
    if (key === "visible") return {visible: {motor, range: v.slice(0, 2)}};
    const spec = {motor, at0: v.slice(0, 2), at1: v.slice(2, 4)};
    if (key === "scale") {  // about the component's centre at rest
      spec.origin = centre(((faces.last.outlines || [])[faces.selected] || []).flat());
    }
    return {[key]: spec};
  }

  const component = (fields) => faces.edit({action: "set_component", component: faces.selected, fields});
  el("cpoint").addEventListener("change", () => {
    pointFields();
    faces.draw();
  });
  el("new-component").addEventListener("click", () => {
    const [x0, y0, x1, y1] = faces.doc.viewbox;
    faces.selected = (faces.doc.components || []).length;  // the new one, drawn last
    faces.chosen = [faces.selected];
    tools.point = null;
    faces.edit({action: "new_component", kind: el("new-kind").value, x: (x0 + x1) / 2, y: (y0 + y1) / 2,
                size: (x1 - x0) / 8});
  });
  el("set-point").addEventListener("click", () => {
    const message = {action: "set_point_kind", component: faces.selected, ...tools.point, kind: el("point-kind").value};
    if (el("point-master").value) message.master = el("point-master").value;
    faces.edit(message);
    pointKindFields.applied();
  });
  el("delete-point").addEventListener("click", () => faces.edit({action: "delete_component_point",
                                                                 component: faces.selected, ...tools.point}));
  el("apply-outline").addEventListener("click", () => {
    const spec = chosen();
    const fields = {smooth: ranges(el("smooth").value), hidden: numbers(el("hidden-segments").value),
                    clip: el("clip").value || null};
    if (!fields.hidden.length) fields.hidden = null;
    if (spec.kind === "polyline" || spec.kind === "skeleton") fields.closed = el("closed").checked;
    if (spec.kind === "skeleton") fields.coupling = el("coupling").value;
    component(fields);
    outlineFields.applied();
  });
  el("set-param").addEventListener("click", () => component(param()));
  el("clear-param").addEventListener("click", () => component({[el("param").value]: null}));
  el("group").addEventListener("click", () => {
    const indices = [...faces.chosen].sort((a, b) => a - b);
    faces.selected = indices[0];
    faces.chosen = [indices[0]];
    faces.edit({action: "group", indices});
  });
  el("ungroup").addEventListener("click", () => faces.edit({action: "ungroup", index: faces.selected}));
  el("list-library").addEventListener("click", () => faces.edit({action: "list_library", library: el("library").value}));
  el("insert-entry").addEventListener("click", () => {
    const controls = Object.fromEntries(el("controls").value.split(",").map((pair) => pair.split("=")
      .map((s) => s.trim())).filter((pair) => pair.length === 2 && pair[0]));
    faces.selected = (faces.doc.components || []).length;
    faces.chosen = [faces.selected];
    faces.edit({action: "insert_from_library", library: el("library").value, use: el("library-entry").value,
                controls});
  });
  el("save-entry").addEventListener("click", () => faces.edit({action: "save_to_library", index: faces.selected,
                                                              library: el("library").value,
                                                              name: el("entry-name").value}));
})();
