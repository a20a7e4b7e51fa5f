// The room's performer page: the browser's camera, MediaPipe's face landmarker in the page (served by the
// room server from its own copy of @mediapipe/tasks-vision and face_landmarker.task, never a CDN), and one
// compact frame a camera frame to the room (face_code.js: the scores the server's mapping reads, once it has
// said which; toonface/room/performers.py maps them, as VMC's). The perform token rides in the address's
// fragment (#perform=TOKEN), which the browser never sends to a server.
import {FaceLandmarker, FilesetResolver} from "/web/tasks-vision/vision_bundle.mjs";
import {FaceCoder} from "/static/face_code.js";

const $ = (id) => document.getElementById(id);
const room = decodeURIComponent(location.pathname.split("/")[2] || "");
const token = new URLSearchParams(location.hash.slice(1)).get("perform") || "";
const performer = {frames: 0, faces: 0, sent: 0, sentBytes: 0, rate: 0, error: null, ready: false};
window.performer = performer;  // the tests read it
$("room").textContent = room;

function fail(text) {
  performer.error = text;
  $("said").hidden = false;
  $("said").textContent = text;
  $("status").textContent = "stopped";
}

function face(result) {
  // the blendshapes by name and the transformation matrix's 16 numbers, or nulls where no face is in view
  const shapes = result.faceBlendshapes && result.faceBlendshapes[0];
  const matrix = result.facialTransformationMatrixes && result.facialTransformationMatrixes[0];
  if (!shapes || !matrix) return {scores: null, matrix: null};
  const scores = {};
  for (const c of shapes.categories) scores[c.categoryName] = c.score;
  return {scores, matrix: matrix.data};
}

function connect() {
  const socket = window.toonRoomLink.open(room, "perform", token, "&format=face");
  performer.coder = null;  // until the server says which scores its mapping reads
  socket.onclose = async () => {
    const state = await window.toonRoomLink.closed(room, "perform", token);
    if (state !== "away") return fail(window.toonRoomLink.said(state, "perform"));  // a wrong link: said, kept
    $("status").textContent = window.toonRoomLink.said(state, "perform");
    setTimeout(() => { performer.socket = connect(); }, 500);
  };
  socket.onmessage = (event) => {  // the scores to send, then what the mapping says: eye contact taken, or why not
    const {said, scores, clock} = JSON.parse(event.data);
    if (Array.isArray(scores)) performer.coder = new FaceCoder(scores);
    if (typeof clock === "number" && performer.started !== undefined) {  // the server asks the frames' clock
      socket.send(JSON.stringify({clock, at: performance.now() - performer.started}));
    }
    if (typeof said === "string") $("contact").textContent = performer.contact = said;
  };
  return socket;
}

async function start() {
  if (!token) return fail("no perform token: open the link the room server printed (it ends in #perform=…)");
  if (!window.isSecureContext || !navigator.mediaDevices) {
    return fail("a browser lends its camera only to https:// pages (or to this machine's own, localhost): start the "
                + "room with --tls-self-signed (or --tls-cert and --tls-key), or behind a TLS proxy");
  }
  let landmarker;
  try {
    const fileset = await FilesetResolver.forVisionTasks("/web/tasks-vision/wasm");
    landmarker = await FaceLandmarker.createFromOptions(fileset, {
      baseOptions: {modelAssetPath: "/web/face_landmarker.task", delegate: "CPU"}, runningMode: "VIDEO",
      numFaces: 1, outputFaceBlendshapes: true, outputFacialTransformationMatrixes: true});
  } catch (error) {
    return fail(`the face tracker did not start (${error.message || error}): the room server may lack its files `
                + "(make browser installs @mediapipe/tasks-vision; pip install 'toonface[faces]' the model)");
  }
  const video = $("camera");
  try {
    video.srcObject = await navigator.mediaDevices.getUserMedia({video: {width: 640, height: 480}, audio: false});
    await video.play();
  } catch (error) {
    return fail(`no camera (${error.name || error}): allow this page to use it, and reload`);
  }
  performer.socket = connect();
  performer.ready = true;
  const started = performer.started = performance.now();  // frames' times (ms) count from here
  const times = [];
  let last = -1;
  $("eye-contact").disabled = false;
  $("eye-contact").onclick = () => {
    if (performer.socket.readyState !== WebSocket.OPEN || !performer.coder) return;
    performer.socket.send(JSON.stringify({eye_contact: true, t: performer.coder.ms}));  // from the newest frame on
    $("contact").textContent = "look at the middle of your screen…";
  };
  const step = () => {
    if (performer.error) return;  // stopped: what stopped it stays on the page
    const ms = performance.now() - started;
    if (ms > last) {  // the landmarker needs increasing times
      last = ms;
      const frame = face(landmarker.detectForVideo(video, performance.now()));
      performer.frames += 1;
      performer.faces += frame.scores ? 1 : 0;
      const sending = performer.socket.readyState === WebSocket.OPEN && performer.coder;
      if (sending) {
        const data = performer.coder.encode(ms, frame.scores, frame.matrix);
        performer.socket.send(data);
        performer.sent += 1;
        performer.sentBytes += data.byteLength;
      }
      const now = performance.now();
      times.push(now);
      while (times.length && times[0] < now - 1000) times.shift();
      performer.rate = times.length;
      $("status").textContent = `${frame.scores ? "face found" : "no face in view"} · ${performer.rate} frames/s`
        + ` · ${sending ? "sending" : "connecting…"}`;
    }
    video.requestVideoFrameCallback(step);
  };
  video.requestVideoFrameCallback(step);
}

start();
