// The mapping tuner's panel: a take mapped on the face, a motor's rule and its sources' ranges to
// edit, its output over the take as a curve. The server (toonface/studio/tuner.py) maps again.
"use strict";
(() => {
  const node = studio.svg;
  const el = (id) => document.getElementById(id);
  const tuner = {state: null};
  window.tuner = tuner;
  const send = (message) => studio.send({op: "tune", ...message});
  const ruleFields = studio.form(["tune-gain", "tune-offset", "tune-scale", "tune-invert", "tune-clamp",
                                  "tune-max_speed", "tune-smoothing", "tune-curve-points"]);  // "tune-apply"

  function show(state) {
    tuner.state = state;
    const code = state.motor;
    el("tune-motor").replaceChildren(...state.motors.map((c) => new Option(c, c, false, c === code)));
    const rule = state.rules[code] || {};
    ruleFields.showing(code);  // what was typed and not applied stays
    const put = ruleFields.put;
    put("tune-gain", "value", rule.gain ?? 1);
    put("tune-offset", "value", rule.offset ?? 0);
    put("tune-scale", "value", rule.scale ?? 1);
    put("tune-invert", "checked", Boolean(rule.invert));
    put("tune-clamp", "value", rule.clamp ?? "hard");
    put("tune-max_speed", "value", rule.max_speed ?? 0);
    put("tune-smoothing", "value", rule.filter && rule.filter.kind === "butterworth" ? rule.filter.cutoff : 0);
    put("tune-curve-points", "value", (rule.curve || []).map(([a, b]) => `${a},${b}`).join(" "));
    el("tune-ranges").replaceChildren(...(state.sources[code] || []).filter((key) => state.ranges[key]).map(range));
    curve();
  }

  function range(key) {
    const [neutral, low, high] = tuner.state.ranges[key];
    const row = document.createElement("div");
    row.className = "tune-range";
    const input = (value) => Object.assign(document.createElement("input"), {type: "number", step: "any", value});
    const fields = [input(low), input(neutral), input(high)];
    const apply = Object.assign(document.createElement("button"), {type: "button", textContent: "Apply range"});
    apply.addEventListener("click", () => send({action: "range", key, low: Number(fields[0].value),
                                                neutral: Number(fields[1].value), high: Number(fields[2].value)}));
    row.append(`${key}: low `, fields[0], " rest ", fields[1], " high ", fields[2], " ", apply);
    return row;
  }

  function curve() {
    const state = tuner.state;
    const svg = el("tune-curve");
    if (!state || !state.curve) return;
    const width = Number(svg.getAttribute("width"));
    const height = Number(svg.getAttribute("height"));
    const x = (t) => (t / state.duration) * width;
    const y = (v) => 4 + (1 - v) * (height - 8);
    const polyline = (values, kind) => node("polyline", {
      class: kind, points: state.curve.times.map((t, i) => `${x(t)},${y(values[i])}`).join(" ")});
    // the sources as the mapping reads them (-1 at the performer's low, 1 at high) under the output (0..1)
    const parts = Object.values(state.curve.sources).map((values) => polyline(values.map((v) => (v + 1) / 2),
                                                                               "source"));
    parts.push(polyline(state.curve.values, "curve"));
    parts.push(node("line", {class: "cursor", x1: 0, x2: 0, y1: 0, y2: height}));
    svg.replaceChildren(...parts);
    raw();
  }

  function moveCursor(now) {
    // the take's time on both plots; the plots themselves are drawn when the tuning changes
    if (!tuner.state || !tuner.state.curve) return;
    const x = (now / tuner.state.duration) * Number(el("tune-curve").getAttribute("width"));
    for (const line of document.querySelectorAll("#tune-curve .cursor, #tune-raw .cursor")) {
      line.setAttribute("x1", x);
      line.setAttribute("x2", x);
    }
  }


  function raw() {
    // each source as measured, in its units (mm, °, score), under the performer's low, rest and high:
    // drag a line to move that end of the range
    const state = tuner.state;
    const svg = el("tune-raw");
    const keys = Object.keys(state.curve.raw).filter((key) => state.ranges[key]);
    const width = Number(svg.getAttribute("width"));
    const row = 76;
    svg.setAttribute("height", row * keys.length);
    if (!tuner.dragged) tuner.rows = {};
    const parts = [];
    keys.forEach((key, k) => {
      const values = state.curve.raw[key];
      const [neutral, low, high] = tuner.dragged && tuner.dragged.key === key ? tuner.dragged.range : state.ranges[key];
      const top = k * row + 16;
      if (!tuner.dragged) {  // a row keeps its scale while one of its lines is dragged
        const seen = values.filter((v) => v !== null);
        const lo = Math.min(low, ...seen);
        const hi = Math.max(high, ...seen);
        const pad = (hi - lo) * 0.08 || 1;
        tuner.rows[key] = {top, height: row - 24, lo: lo - pad, span: hi - lo + 2 * pad};
      }
      const scale = tuner.rows[key];
      const y = (v) => top + (1 - (v - scale.lo) / scale.span) * scale.height;
      const x = (i) => (state.curve.times[i] / state.duration) * width;
      const unit = state.curve.units[key];
      const label = node("text", {class: "raw-label", x: 2, y: top - 3});
      label.textContent = `${key}: ${low.toFixed(2)} to ${high.toFixed(2)} ${unit}, rest ${neutral.toFixed(2)}`;
      parts.push(label);
      const points = values.map((v, i) => (v === null ? null : `${x(i)},${y(v)}`)).filter(Boolean).join(" ");
      parts.push(node("polyline", {class: "raw", points}));
      [["low", low], ["rest", neutral], ["high", high]].forEach(([which, v]) => {
        parts.push(node("line", {class: `raw-range ${which}`, x1: 0, x2: width, y1: y(v), y2: y(v),
                                 "data-key": key, "data-which": which}));
      });
      parts.push(node("line", {class: "cursor", x1: 0, x2: 0, y1: top, y2: top + row - 24}));
    });
    svg.replaceChildren(...parts);
  }

  function rawValue(event, key) {
    // the source's value at the pointer's height in its row
    const {top, height, lo, span} = tuner.rows[key];
    const box = el("tune-raw").getBoundingClientRect();
    const y = event.clientY - box.top;
    return lo + (1 - (y - top) / height) * span;
  }

  el("tune-raw").addEventListener("pointerdown", (event) => {
    const {key, which} = event.target.dataset || {};
    if (!key) return;
    tuner.dragged = {key, which, range: [...tuner.state.ranges[key]]};
    el("tune-raw").setPointerCapture(event.pointerId);
    event.preventDefault();
  });
  el("tune-raw").addEventListener("pointermove", (event) => {
    const drag = tuner.dragged;
    if (!drag) return;
    drag.range[{rest: 0, low: 1, high: 2}[drag.which]] = rawValue(event, drag.key);
    raw();
  });
  el("tune-raw").addEventListener("pointerup", () => {
    const drag = tuner.dragged;
    if (!drag) return;
    tuner.dragged = null;
    const [neutral, low, high] = drag.range;
    send({action: "range", key: drag.key, neutral, low, high});
  });

  studio.handlers.tune = show;
  const drawn = studio.onFrame;
  studio.onFrame = (frame) => {
    if (drawn) drawn(frame);
    if (frame.showing === "tune") moveCursor(frame.tune_time);
  };
  el("tune-open").addEventListener("click", () => send({action: "open", take: el("tune-take").value,
                                                        mapping: el("tune-mapping").value || null,
                                                        units: el("tune-units").value || null}));
  el("tune-pause").addEventListener("click", () => send({action: "pause"}));
  el("tune-play").addEventListener("click", () => send({action: "play"}));
  el("tune-motor").addEventListener("change", (event) => send({action: "motor", code: event.target.value}));
  el("tune-apply").addEventListener("click", () => {
    const code = el("tune-motor").value;
    const fields = {gain: Number(el("tune-gain").value), offset: Number(el("tune-offset").value),
                    scale: Number(el("tune-scale").value), invert: el("tune-invert").checked,
                    clamp: el("tune-clamp").value, max_speed: Number(el("tune-max_speed").value)};
    const rule = tuner.state.rules[code] || {};
    for (const [field, value] of Object.entries(fields)) {
      const defaults = {gain: 1, offset: 0, scale: 1, invert: false, clamp: "hard", max_speed: 0};
      if ((rule[field] ?? defaults[field]) !== value) send({action: "rule", code, field, value});
    }
    const cutoff = Number(el("tune-smoothing").value);
    const filter = cutoff > 0 ? {kind: "butterworth", cutoff} : null;
    if (JSON.stringify(rule.filter ?? null) !== JSON.stringify(filter)) send({action: "rule", code, field: "filter",
                                                                             value: filter});
    const text = el("tune-curve-points").value.trim();
    const curve = text ? text.split(/\s+/).map((pair) => pair.split(",").map(Number)) : null;
    if (JSON.stringify(rule.curve ?? null) !== JSON.stringify(curve)) send({action: "rule", code, field: "curve",
                                                                           value: curve});
    ruleFields.applied();
  });
  el("tune-save-mapping").addEventListener("click", () => send({action: "save_mapping",
                                                                path: el("tune-mapping-path").value}));
  el("tune-save-profile").addEventListener("click", () => send({action: "save_profile",
                                                                path: el("tune-profile-path").value}));
})();
