// Files through the browser (toonface/studio/files.py): a file dropped anywhere on the page, or chosen
// with "Open file…", is sent to the studio, kept in its working folder, and opened where it belongs.
"use strict";
(() => {
  const el = (id) => document.getElementById(id);
  const files = {sent: 0, last: null};
  window.files = files;  // the tests read it

  const RECENT = "toonface.studio.recent";  // this browser's last files opened, newest first
  const KEPT = 10;

  function recent() {
    try {
      return JSON.parse(localStorage.getItem(RECENT) || "[]").filter((f) => f && f.name && f.kind);
    } catch (error) {
      return [];
    }
  }

  function listRecent() {
    el("recent").replaceChildren(new Option("…", ""), ...recent().map((f, i) => new Option(f.name, String(i))));
  }

  function remember(name, kind) {
    const kept = [{name, kind}, ...recent().filter((f) => f.name !== name)].slice(0, KEPT);
    localStorage.setItem(RECENT, JSON.stringify(kept));
    listRecent();
  }

  function open(name, kind) {
    // the file, now in the working folder, opened by the studio's own commands
    remember(name, kind);
    if (kind === "editor") {
      el("path").value = name.endsWith(".toml") ? name : "";
      editor.open(name);
    } else if (kind === "sound") studio.send({op: "sound", path: name});
    else if (kind === "labels") studio.send({op: "labels", path: name});
    else if (kind === "face") studio.send({op: "face", name});
    else if (kind === "artwork") {  // your own drawing, into the face being edited
      el("tab-face").click();
      el("target-component").click();
      faces.edit({action: name.toLowerCase().endsWith(".png") ? "import_picture" : "import_svg", path: name});
    }
  }

  async function send(file) {
    studio.say(`sending ${file.name}…`, false);
    const response = await fetch(`/files/${encodeURIComponent(file.name)}`, {method: "POST", body: file});
    if (!response.ok) {
      studio.say(`${file.name}: ${(await response.text()).trim()}`, true);
      return;
    }
    const kept = await response.json();
    files.sent += 1;
    files.last = kept;
    studio.say(`${file.name} is in the studio's folder as ${kept.name}: opening it…`, false);
    open(kept.name, kept.kind);
  }
  files.send = send;

  files.open = open;
  listRecent();
  el("recent").addEventListener("change", (event) => {
    const chosen = event.target.value === "" ? null : recent()[Number(event.target.value)];
    event.target.value = "";
    if (chosen) open(chosen.name, chosen.kind);
  });
  el("open").addEventListener("click", () => {  // a name typed and opened is recent too
    if (el("path").value) remember(el("path").value, "editor");
  });
  el("svg-picker").addEventListener("change", (event) => {
    for (const file of event.target.files) send(file);
    event.target.value = "";
  });
  el("attach-component").addEventListener("click", () => {
    faces.edit({action: "attach", component: faces.selected, feature: el("attach-feature").value});
  });
  el("file-picker").addEventListener("change", (event) => {
    for (const file of event.target.files) send(file);
    event.target.value = "";
  });
  let depth = 0;  // dragenter and dragleave come for every element the drag crosses
  document.addEventListener("dragenter", (event) => {
    if (![...event.dataTransfer.types].includes("Files")) return;
    depth += 1;
    el("drop").hidden = false;
  });
  document.addEventListener("dragleave", () => {
    depth = Math.max(0, depth - 1);
    if (!depth) el("drop").hidden = true;
  });
  document.addEventListener("dragover", (event) => event.preventDefault());
  document.addEventListener("drop", (event) => {
    event.preventDefault();
    depth = 0;
    el("drop").hidden = true;
    for (const file of event.dataTransfer.files) send(file);
  });
})();
