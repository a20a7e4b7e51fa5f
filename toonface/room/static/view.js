// The room's viewer page. It draws the performers' faces itself (face_stream.js): it is sent their
// motor packets as a native viewer is, and the face's web rig once (/face.json); a sealed stream
// opens with the key in the fragment (#watch=TOKEN&key=BASE64URL), which the server never sees: it
// relays bytes it cannot read. With ?draw=server the server draws them instead
// (toonface/room/stage.py) and the page shows its drawings (draw.js), at hundreds of kbit/s. The
// watch token rides in the address's fragment (#watch=TOKEN), which the browser never sends to a
// server; ?obs gives a clear page for OBS's browser source.
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

  function arrange() {
    // the faces as large as the window lets all of them be at once, in as many columns as does
    // that best (two performers stacked put the second below the fold: issue 68)
    const count = Math.max(1, viewer.performers.size), header = $("stage").offsetTop + 16;
    const width = window.innerWidth - 32, height = window.innerHeight - header;
    let best = 0;
    for (let columns = 1; columns <= count; columns++) {
      const rows = Math.ceil(count / columns);
      const size = Math.min((width - (columns - 1) * 16) / columns, (height - (rows - 1) * 16) / rows - 28, 512);
      best = Math.max(best, size);
    }
    $("stage").style.setProperty("--face", `${Math.max(64, Math.floor(best))}px`);
  }
  window.addEventListener("resize", arrange);

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
      arrange();
    }
    return performer;
  }

  function unseat(id) {
    const performer = viewer.performers.get(id);
    if (performer) performer.figure.remove();
    viewer.performers.delete(id);
    arrange();
  }

  function readout(q, link = 0) {
    // LINK: the server-drawn page's delay from the server's drawing to this screen (ms)
    const latency = q.latency_ms === null ? "–" : `${Math.round(q.latency_ms + link)} ms`;
    return `latency ${latency} · loss ${q.loss_pct} % · concealed ${q.concealed_pct} %`
      + (q.diagnosis ? ` · ${q.diagnosis}` : "");
  }

  function show(message) {
    for (const id of message.gone) unseat(id);
    for (const frame of message.performers) {
      const performer = seat(frame.id);
      performer.drawing.held = viewer.held;
      performer.drawing.show(frame);
      if (viewer.held) continue;
      performer.quality = frame.quality;  // what is shown: its values too
      performer.caption.textContent = `performer ${frame.id.toString(16)} · `
        + readout(frame.quality, viewer.linkMs || 0);
    }
    $("said").hidden = !message.said;
    $("said").textContent = message.said || "";
    if (!message.performers.length) $("status").textContent = "connected: waiting for a performer…";
    else $("status").textContent = `${message.performers.length} performer${message.performers.length > 1 ? "s" : ""}`;
    viewer.last = message;
    viewer.frames += 1;
  }

  function connect() {
    const socket = toonRoomLink.open(room, "watch", token, "&format=drawn");
    socket.binaryType = "arraybuffer";
    let queue = Promise.resolve();  // messages are shown in the order they came
    socket.onopen = () => { viewer.connected = true; $("status").textContent = "connected"; };
    socket.onmessage = (event) => {
      if (typeof event.data === "string") {  // the server's word: this link's delay, sent to shown
        const said = JSON.parse(event.data);
        if (typeof said.delay_ms === "number") viewer.linkMs = said.delay_ms;
        return;
      }
      queue = queue.then(() => toonDraw.inflate(event.data)).then((message) => {
        show(message);
        if (socket.readyState === WebSocket.OPEN) socket.send("s");  // shown: the server sends the next
      });
    };
    socket.onclose = () => closed(connect);  // another server process on the address may take it
  }
  async function closed(again) {
    // a wrong link is said and left; a server away is tried again in half a second
    viewer.connected = false;
    const state = await toonRoomLink.closed(room, "watch", token);
    $("status").textContent = toonRoomLink.said(state, "watch");
    viewer.refused = state !== "away";
    if (state === "away") setTimeout(again, 500);
  }
  const GONE_SECONDS = 2.0;  // a performer silent this long leaves the page (one who leaves is said at once)

  async function drawHere() {
    // the page's own drawing: packets in, the faces drawn at the screen's rate
    const response = await fetch("/face.json");
    if (!response.ok) throw new Error(`the face did not load (${response.status})`);
    const rig = new toonRig.Rig(await response.json());
    const key = fragment.get("key") ? await toonWire.streamKey(secretOf(fragment.get("key"))) : null;
    const streams = new Map();
    // this page's clock less the server's, from the answer of the shortest round trip of the last
    // minute, and each performer's less the server's as the server tells them (s): toonface/room/clocks.py
    const clocks = {offset: null, trip: Infinity, when: 0, performers: new Map()};
    let socket = null;
    Object.assign(viewer, {bytes: 0, messages: 0, sentBytes: 0, sent: 0, firstDrawMs: null});
    const send = (bytes) => {
      if (!socket || socket.readyState !== WebSocket.OPEN) return;
      socket.send(bytes);
      viewer.sentBytes += bytes.length;
      viewer.sent += 1;
    };
    function open() {
      socket = toonRoomLink.open(room, "watch", token);
      socket.binaryType = "arraybuffer";
      socket.onopen = () => {
        // (again) connected: the server may be another process, which knows none of the faces shown
        for (const id of [...streams.keys()]) { unseat(id); streams.delete(id); }
        Object.assign(clocks, {offset: null, trip: Infinity, when: 0});  // another server may keep another clock
        clocks.performers.clear();
        send(JSON.stringify({clock: performance.now()}));
        viewer.connected = true;
        $("status").textContent = "connected: waiting for a performer…";
      };
      socket.onmessage = (event) => {
        if (typeof event.data === "string") {  // the server's word: performers who left, clocks
          const said = JSON.parse(event.data), now = performance.now();
          for (const id of said.gone || []) { unseat(id); streams.delete(id); }
          for (const [id, ms] of Object.entries(said.clocks || {})) clocks.performers.set(Number(id), ms / 1000);
          if (typeof said.at === "number" && (now - said.clock <= clocks.trip || now - clocks.when > 60000)) {
            Object.assign(clocks, {trip: now - said.clock, when: now, offset: ((said.clock + now) / 2 - said.at) / 1000});
          }
          return;
        }
        const bytes = new Uint8Array(event.data), now = performance.now() / 1000;
        if (bytes.length < 3) return;
        const id = bytes[1] | (bytes[2] << 8);
        if (!streams.has(id)) streams.set(id, new toonFaceStream.FaceStream(rig, seat(id).drawing, send, key));
        streams.get(id).feed(bytes, now);
        viewer.bytes += bytes.length;
        viewer.messages += 1;
      };
      socket.onclose = () => closed(open);
    }
    setInterval(() => send(JSON.stringify({clock: performance.now()})), 2000);  // the server's clock, asked
    viewer.clocks = clocks;
    viewer.frameMs = [];  // the last 240 frames' drawing times (the bench reads them)
    function tick() {
      const now = performance.now() / 1000, shown = [];
      for (const [id, stream] of streams) {
        const performer = seat(id);
        if (now - stream.received > GONE_SECONDS) {
          unseat(id);
          streams.delete(id);
          continue;
        }
        performer.drawing.held = viewer.held;
        if (!stream.draw(now)) continue;
        const known = clocks.offset !== null && clocks.performers.has(id);  // else the same clock is assumed
        const q = stream.quality(known ? clocks.offset - clocks.performers.get(id) : 0);
        const values = Object.fromEntries(rig.codes.map((c, i) => [c, stream.last[i]]));
        const quality = {values, latency_ms: q.latency, loss_pct: Number(q.loss.toFixed(1)),
          concealed_pct: Number(q.concealed.toFixed(1)), diagnosis: null};
        shown.push({id, values, quality});
        if (viewer.held) continue;
        performer.quality = quality;  // what is shown: its values too
        performer.caption.textContent = `performer ${id.toString(16)} · ${readout(quality)}`;
      }
      for (const [id, stream] of streams) {  // a stream that never opened: say why
        if (stream.reader.packets || !stream.reader.dropped.tag) continue;
        seat(id).caption.textContent = `performer ${id.toString(16)} · its packets do not open: `
          + (key ? "another key, or corrupted" : "sealed (add the key to the link: #watch=…&key=…)");
      }
      if (shown.length) {
        if (viewer.firstDrawMs === null) viewer.firstDrawMs = performance.now();
        viewer.frameMs.push(performance.now() - 1000 * now);
        if (viewer.frameMs.length > 240) viewer.frameMs.shift();
        viewer.last = {performers: shown};
        viewer.frames += 1;
        $("status").textContent = `${shown.length} performer${shown.length > 1 ? "s" : ""}`;
      }
      requestAnimationFrame(tick);
    }
    open();
    requestAnimationFrame(tick);
  }

  function secretOf(text) {
    // the stream's key from the link (base64url, as `send --key-file` prints it)
    let plain;
    try {
      plain = atob(text.replace(/-/g, "+").replace(/_/g, "/").padEnd(Math.ceil(text.length / 4) * 4, "="));
    } catch {
      throw new Error("the key in the link is not base64url (copy it as send --key-file printed it)");
    }
    return Uint8Array.from(plain, (c) => c.charCodeAt(0));
  }

  if (query.get("draw") === "server") connect();
  else drawHere().catch((error) => { $("said").hidden = false; $("said").textContent = String(error.message || error); });
})();
