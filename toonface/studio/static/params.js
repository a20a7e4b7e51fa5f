// The face editor's parameters beyond the 21 motors (toon/params.py): declare one, say where it
// rests and which control points it moves how far; the server checks the face and answers with a
// slider and a staff for it (toonface/studio/faces.py set_param, delete_param).
(() => {
"use strict";
  const el = (id) => document.getElementById(id);
  const STANDARD = ["UL", "CP", "JS", "PERK"];  // the standard extras a face may declare (HT: head.tilt)

  function list(doc) {
    const params = doc.params || {};
    el("fparam-codes").replaceChildren(...[...new Set([...STANDARD, ...Object.keys(params)])].map((c) => new Option(c)));
    const points = Object.keys(doc.points);
    const point = el("fparam-point");
    const keep = point.value;
    point.replaceChildren(...points.map((name) => new Option(name, name, false, name === keep)));
    el("fparam-list").replaceChildren(...Object.entries(params).map(([code, body]) => {
      const row = document.createElement("div");
      row.className = "fparam";
      row.dataset.code = code;
      const moves = Object.entries(body.points || {}).map(([name, m]) =>
        `${name} (${m.at0.map((v) => +v.toFixed(1)).join(", ")}) to (${m.at1.map((v) => +v.toFixed(1)).join(", ")})`);
      row.textContent = `${code}, rests at ${body.neutral ?? 0}: ${moves.join("; ") || "moves no point"}`;
      row.title = body.description || "";
      row.addEventListener("click", () => { el("fparam-code").value = code; el("fparam-neutral").value = body.neutral ?? 0; });
      return row;
    }));
  }

  function drivers(doc) {
    const params = [...(doc.head && doc.head.tilt ? ["HT"] : []), ...Object.keys(doc.params || {})];
    const param = el("driver-param");
    const keep = param.value;
    param.replaceChildren(...params.map((code) => new Option(code, code, false, code === keep)));
    el("driver-list").replaceChildren(...(doc.physics || []).map((d) => {
      const row = document.createElement("div");
      row.className = "driver";
      row.dataset.name = d.name;
      const primes = {velocity: "'", acceleration: "''"};
      const inputs = d.inputs.map((i) => i.driver ? `${i.driver}>:${i.gain}` : `${i.code}${primes[i.of] || ""}:${i.gain}`);
      row.textContent = `${d.name}: ${d.output.param} ${d.output.swing ? "swings" : "follows"} ${inputs.join(" ")}`
        + ` at ${d.frequency} Hz, damping ${d.damping}`;
      row.addEventListener("click", () => {  // chosen to tune: its fields filled in
        el("driver-name").value = d.name;
        el("driver-param").value = d.output.param;
        el("driver-inputs").value = inputs.join(" ");
        el("driver-frequency").value = d.frequency;
        el("driver-damping").value = d.damping;
        el("driver-swing").checked = d.output.swing;
      });
      return row;
    }));
  }

  el("driver-set").addEventListener("click", () => faces.edit({
    action: "set_driver", name: el("driver-name").value.trim(), param: el("driver-param").value,
    inputs: el("driver-inputs").value, frequency: Number(el("driver-frequency").value),
    damping: Number(el("driver-damping").value), swing: el("driver-swing").checked ? 1 : 0}));
  el("driver-delete").addEventListener("click", () => faces.edit({action: "delete_driver", name: el("driver-name").value.trim()}));

  el("fparam-set").addEventListener("click", () => {
    const code = el("fparam-code").value.trim().toUpperCase();
    const message = {action: "set_param", code, point: el("fparam-point").value,
                     dx: Number(el("fparam-dx").value), dy: Number(el("fparam-dy").value)};
    if (!STANDARD.includes(code)) message.neutral = Number(el("fparam-neutral").value);
    faces.edit(message);
  });
  el("fparam-delete").addEventListener("click", () =>
    faces.edit({action: "delete_param", code: el("fparam-code").value.trim().toUpperCase()}));

  const shown = studio.handlers.face;
  studio.handlers.face = (message) => {
    shown(message);
    list(message.doc);
    drivers(message.doc);
  };
})();
