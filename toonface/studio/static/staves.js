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
    const knot = picked();
    el("knot-edit").hidden = knot === null;
    if (!knot) return;
    const [code, index, [t, v]] = knot;
    el("knot-name").textContent = `${code} knot ${index + 1}`;
    for (const [id, value] of [["knot-t", t], ["knot-v", v]]) {
      if (document.activeElement === el(id)) continue;
      el(id).value = value.toFixed(3);
      el(id).dataset.shown = el(id).value;  // what was shown: left as it is, the knot's own value stays
    }
  };

  function read(id, exact) {
    const field = el(id);
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

  el("knot-t").addEventListener("change", typed);
  el("knot-v").addEventListener("change", typed);
})();
