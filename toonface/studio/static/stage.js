// Zoom and pan on the face: the wheel zooms about the pointer, a middle-button (or Alt) drag pans,
// 0 shows the whole face again. The face, its control points and the editor's handles move as one
// (a CSS transform on each); every pointer position is read back through the SVG's own transform.
"use strict";
(() => {
  const el = (id) => document.getElementById(id);
  const view = {scale: 1, x: 0, y: 0, panning: null};
  window.stageView = view;  // the tests read it
  const layers = () => [el("view"), el("handles"), el("shape")];

  function apply() {
    for (const layer of layers()) {
      layer.style.transformOrigin = "0 0";
      layer.style.transform = view.scale === 1 && !view.x && !view.y ? ""
        : `translate(${view.x}px, ${view.y}px) scale(${view.scale})`;
    }
  }

  function zoomAt(factor, clientX, clientY) {
    const box = el("stage").getBoundingClientRect();
    const px = clientX - box.left;
    const py = clientY - box.top;
    const scale = Math.min(16, Math.max(1, view.scale * factor));
    const k = scale / view.scale;
    view.x = px - (px - view.x) * k;  // the point under the pointer stays under it
    view.y = py - (py - view.y) * k;
    view.scale = scale;
    if (scale === 1) view.x = view.y = 0;
    apply();
  }
  view.zoomAt = zoomAt;
  view.reset = () => { view.scale = 1; view.x = view.y = 0; apply(); };

  el("stage").addEventListener("wheel", (event) => {
    event.preventDefault();
    zoomAt(Math.exp(-event.deltaY / 400), event.clientX, event.clientY);
  }, {passive: false});
  el("stage").addEventListener("pointerdown", (event) => {
    if (event.button !== 1 && !(event.button === 0 && event.altKey)) return;
    view.panning = [event.clientX - view.x, event.clientY - view.y];
    el("stage").setPointerCapture(event.pointerId);
    event.preventDefault();
    event.stopPropagation();
  }, {capture: true});
  el("stage").addEventListener("pointermove", (event) => {
    if (!view.panning) return;
    [view.x, view.y] = [event.clientX - view.panning[0], event.clientY - view.panning[1]];
    apply();
  });
  el("stage").addEventListener("pointerup", () => { view.panning = null; });
  document.addEventListener("keydown", (event) => {
    const tag = event.target.tagName;
    if (tag === "INPUT" || tag === "SELECT" || tag === "TEXTAREA" || event.ctrlKey || event.metaKey) return;
    if (event.key === "0") view.reset();
  });
})();
