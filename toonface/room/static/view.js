// The room's viewer page: the performers' faces as the room server draws them (toonface/room/stage.py),
// shown with the studio's drawing module (draw.js). The watch token rides in the address's fragment
// (#watch=TOKEN), which the browser never sends to a server; ?obs gives a clear page for OBS's browser source.
"use strict";
(() => {
  const $ = (id) => document.getElementById(id);
  const room = decodeURIComponent(location.pathname.split("/")[2] || "");
  const fragment = new URLSearchParams(location.hash.slice(1));
  const token = fragment.get("watch") || fragment.get("token") || "";
  const query = new URLSearchParams(location.search);
  const viewer = {frames: 0, performers: new Map(), last: null, connected: false, held: false};
  window.viewer = viewer;  // the tests read it
  if (query.has("obs")) document.body.classList.add("obs");
  $("hold").addEventListener("click", () => hold(!viewer.held));
  document.addEventListener("keydown", (event) => {
    if (event.key === " " && event.target === document.body) {
      hold(!viewer.held);
      event.preventDefault();
    }
  });

  function hold(on) {
    // hold the picture (space): the stream goes on underneath, and shows again when let go
    viewer.held = on;
    $("hold").setAttribute("aria-pressed", String(on));
    $("hold").textContent = on ? "Go on" : "Hold";
  }
  $("room").textContent = room;

  function seat(id) {
    // the figure of performer `id`, made when it first comes
    let performer = viewer.performers.get(id);
    if (!performer) {
      const figure = document.createElement("figure");
      figure.dataset.performer = id;
      const face = document.createElement("div");
      face.className = "face";
      const caption = document.createElement("figcaption");
      figure.append(face, caption);
      $("stage").append(figure);
      performer = {figure, caption, drawing: new toonDraw.Drawing(face), quality: null};
      viewer.performers.set(id, performer);
    }
    return performer;
  }

  function readout(q) {
    const latency = q.latency_ms === null ? "–" : `${q.latency_ms} ms`;
    return `latency ${latency} · loss ${q.loss_pct} % · concealed ${q.concealed_pct} %`
      + (q.diagnosis ? ` · ${q.diagnosis}` : "");
  }

  function show(message) {
    for (const id of message.gone) {
      const performer = viewer.performers.get(id);
      if (performer) performer.figure.remove();
      viewer.performers.delete(id);
    }
    for (const frame of message.performers) {
      const performer = seat(frame.id);
      performer.drawing.held = viewer.held;
      performer.drawing.show(frame);
      if (viewer.held) continue;
      performer.quality = frame.quality;  // what is shown: its values too
      performer.caption.textContent = `performer ${frame.id.toString(16)} · ${readout(frame.quality)}`;
    }
    $("said").hidden = !message.said;
    $("said").textContent = message.said || "";
    if (!message.performers.length) $("status").textContent = "connected: waiting for a performer…";
    else $("status").textContent = `${message.performers.length} performer${message.performers.length > 1 ? "s" : ""}`;
    viewer.last = message;
    viewer.frames += 1;
  }

  function connect() {
    const scheme = location.protocol === "https:" ? "wss" : "ws";
    const socket = new WebSocket(`${scheme}://${location.host}/r/${encodeURIComponent(room)}/ws?role=watch`
                                 + `&format=drawn&token=${encodeURIComponent(token)}`);
    socket.binaryType = "arraybuffer";
    let queue = Promise.resolve();  // messages are shown in the order they came
    socket.onopen = () => { viewer.connected = true; $("status").textContent = "connected"; };
    socket.onmessage = (event) => {
      queue = queue.then(() => toonDraw.inflate(event.data)).then(show);
    };
    socket.onclose = () => {
      viewer.connected = false;
      $("status").textContent = token ? "disconnected (a wrong token, or the server is away): trying again…"
        : "no watch token: open the link the room server printed (it ends in #watch=…)";
      setTimeout(connect, 500);  // another server process on the address takes it
    };
  }
  connect();
})();
