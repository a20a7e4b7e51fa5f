"""The motor stream read in the page (issue 63): ``stream.js`` and ``stream_reader.js`` in Chromium
read the datagrams a :class:`~stream.packets.StreamWriter` sends over a bad link (packets lost,
late, repeated, replayed from long ago and corrupted, the writer answering the acknowledgements
and keyframe requests the Python reader sends it) exactly as :class:`~stream.reader.StreamReader`
does: the same frames (index, time, values, parameters, run, filled), the same acknowledgement
bytes, the same keyframe requests, drops and losses, datagram by datagram."""

from __future__ import annotations

import json
from importlib import resources

import numpy as np
import pytest
from browser import chromium
from motor_streams import RATE, smooth_motion

from stream.packets import StreamWriter, key_request, read_ack
from stream.reader import StreamReader
from toon.motors import STANDARD_EXTRAS


def lossy_link(seed: int, codes: tuple[str, ...], frames_per_packet: int, steps: int, frames: int = 600,
               key: bytes | None = None) -> list[dict]:
    """Datagrams through a bad link (sealed with ``key`` where given), each with what the Python
    reader made of it."""
    rng = np.random.default_rng(seed)
    values = smooth_motion(frames, seed)
    if codes:
        extra = np.clip(0.5 + 0.4 * np.sin(np.arange(frames)[:, None] / 17.0 + np.arange(len(codes))), 0, 1)
        values = np.column_stack([values, extra])
    writer = StreamWriter(RATE, frames_per_packet=frames_per_packet, first_sequence=int(rng.integers(0, 2 ** 32)),
                          codes=codes, steps=steps, stream=7, key=key)
    reader = StreamReader(key)
    events: list[dict] = []
    late: list[bytes] = []
    sent: list[bytes] = []
    for i, row in enumerate(values):
        datagram = writer.push(row, i / RATE)
        if datagram is None:
            continue
        sent.append(datagram)
        arriving = []
        chance = rng.uniform()
        if chance >= 0.2:
            arriving.append(datagram)
        elif chance >= 0.1:  # below 0.1: lost
            late.append(datagram)
        if chance > 0.9 and late:
            arriving.append(late.pop(0))
        if rng.uniform() < 0.03:
            arriving.append(datagram)  # twice
        if rng.uniform() < 0.03 and len(sent) > 80:
            arriving.append(sent[-80])  # replayed from long ago
        if rng.uniform() < 0.02:
            bad = bytearray(datagram)
            bad[len(bad) // 2] ^= 0x40
            arriving.append(bytes(bad))
        for packet in arriving:
            arrival = i / RATE + 0.01
            got = reader.read(packet, arrival)
            ack = reader.take_ack()
            events.append({"packet": list(packet), "arrival": arrival, "ack": list(ack) if ack else None,
                           "want": reader.want_keyframe, "dropped": dict(reader.dropped), "lost": reader.lost,
                           "frames": [{"first": f.first, "time": f.time_s, "rate": f.rate, "values": f.values.tolist(),
                                       "codes": list(f.codes), "run": f.run, "filled": f.filled} for f in got]})
            if ack and (said := read_ack(ack, key, writer.frame)) is not None:
                writer.acknowledge(*said)
            if reader.want_keyframe:
                writer.request_keyframe()
    return events


READ = """
const [events, secret, done] = [arguments[0], arguments[1], arguments[arguments.length - 1]];
(async () => {
const key = secret ? await toonWire.streamKey(Uint8Array.from(secret)) : null;
const reader = new toonStream.StreamReader(key), out = [];
for (const e of events) {
  const frames = reader.read(new Uint8Array(e.packet), e.arrival).map(({arrival, ...f}) => f);
  const ack = reader.takeAck();
  out.push({frames, ack: ack ? [...ack] : null, want: reader.wantKeyframe, dropped: {...reader.dropped},
            lost: reader.lost});
}
done(out);
})().catch((e) => done({error: String(e)}));
"""


def _page(driver) -> None:
    driver.get("about:blank")
    static = resources.files("toonface.studio").joinpath("static")
    for name in ("stream.js", "stream_reader.js", "playout.js"):
        driver.execute_script("const s = document.createElement('script'); s.text = arguments[0];"
                              "document.head.append(s)", static.joinpath(name).read_text(encoding="utf-8"))


@pytest.mark.slow
@pytest.mark.parametrize("seed, codes, frames_per_packet, steps", [
    (0, ("HT", "CP", "BEARD"), 2, 100), (1, (), 1, 100), (2, ("JS",), 3, 37)])
def test_the_page_reads_a_bad_link_as_the_python_reader_does(seed, codes, frames_per_packet, steps):
    events = lossy_link(seed, codes, frames_per_packet, steps)
    drops = events[-1]["dropped"]
    assert drops.get("replay", 0) > 10 and drops.get("tag", 0) > 5 and events[-1]["lost"] > 20  # the link was bad
    assert sum(len(e["frames"]) for e in events) > 400
    with chromium() as driver:
        _page(driver)
        driver.set_script_timeout(60)
        page = driver.execute_async_script(READ, events, None)
    _same(page, events)


def _same(page: list | dict, events: list[dict]) -> None:
    assert isinstance(page, list), page
    assert len(page) == len(events)
    for k, (mine, theirs) in enumerate(zip(page, events, strict=True)):
        expected = {name: theirs[name] for name in ("frames", "ack", "want", "dropped", "lost")}
        assert _numbers(mine) == _numbers(expected), f"datagram {k}"


@pytest.mark.slow
def test_the_page_opens_a_sealed_stream_with_the_key_as_the_python_does():
    """Sealed (AES-256-GCM-SIV under HKDF-SHA256, noble's code as the room server serves it): the
    same frames, and acknowledgement bytes sealed alike; a corrupted packet does not open."""
    from toonface.room.server import Rooms
    from toonface.room.threaded import in_thread

    secret = b"a shared secret of the room 0123"
    events = lossy_link(4, ("HT",), 2, 100, frames=300, key=secret)
    assert events[-1]["dropped"].get("tag", 0) > 0 and any(e["ack"] for e in events)
    tokens = {"demo": ("perform-secret-0123456789", "watch-secret-0123456789")}
    with in_thread(Rooms(tokens)) as base, chromium() as driver:
        driver.get(f"{base.replace('ws://', 'http://')}/r/demo")  # a page of the server's: its scripts, noble's
        driver.set_script_timeout(60)
        page = driver.execute_async_script(READ, events, list(secret))
    _same(page, events)


def _numbers(found: object) -> object:
    """``found`` with every number a float (the browser gives 60 for 60.0)."""
    return json.loads(json.dumps(found), parse_int=float)


def test_the_pages_constants_are_the_pythons():
    """What the page keeps of the format beside the Python: the parameters' rests, a keyframe
    request's bytes, every residual model's counts (all 255 quantisations)."""
    from stream.wire import Models

    with chromium() as driver:
        _page(driver)
        rests = driver.execute_script("return toonWire.EXTRA_REST")
        request = driver.execute_script("return [...new toonStream.StreamReader().keyframeRequest()]")
        models = driver.execute_script("const out = {}; for (let s = 1; s < 256; s++) "
                                       "out[s] = new toonWire.Models(s).residual.map((m) => m.freq); return out")
    assert rests == {code: spec.neutral for code, spec in STANDARD_EXTRAS.items()}
    assert bytes(request) == key_request(0, None, 0)
    for steps in range(1, 256):
        assert models[str(steps)] == [m.freq for m in Models(steps).residual], f"steps {steps}"


PLAY = """
const [timeline, neutral, done] = [arguments[0], arguments[1], arguments[arguments.length - 1]];
const playout = new toonPlayout.Playout(neutral, {declared: {BEARD: 0.25}}), out = [];
for (const [kind, at, frames] of timeline) {
  if (kind === "add") for (const f of frames) playout.add({...f, arrival: at});
  else { const [values, state] = playout.valuesAt(at); out.push([values, state, playout.delay]); }
}
done(out);
"""


@pytest.mark.slow
@pytest.mark.parametrize("seed, codes", [(0, ("HT", "CP", "BEARD")), (1, ())])
def test_the_pages_playout_shows_what_the_pythons_shows(seed, codes):
    """The jitter buffer, concealment and catching up of ``playout.js`` against
    :class:`stream.playout.Playout`, fed the same frames over a bad link and asked at 60 Hz: the
    same values (to 1e-9), states and delays."""
    from stream.playout import Playout
    from stream.reader import Frames
    from toon import standard_neutral

    events = lossy_link(seed, codes, 2, 100)
    timeline: list[tuple[str, float, list]] = [("add", e["arrival"], e["frames"]) for e in events if e["frames"]]
    end = timeline[-1][1]
    timeline += [("draw", k / 60 + 0.005, []) for k in range(int(end * 60) + 30)]
    timeline.sort(key=lambda item: (item[1], item[0] == "draw"))
    playout = Playout(standard_neutral(), declared={"BEARD": 0.25})
    expected = []
    for kind, at, frames in timeline:
        if kind == "add":
            for f in frames:
                playout.add(Frames(f["first"], f["time"], f["rate"], np.array(f["values"]), at, tuple(f["codes"]),
                                   f["run"], f["filled"]))
        else:
            values, state = playout.values_at(at)
            expected.append((values, state, playout.delay))
    states = [state for _, state, _ in expected]
    assert states.count("concealed") > 10 and states.count("recovering") > 0 and states.count("live") > 300
    with chromium() as driver:
        _page(driver)
        driver.set_script_timeout(60)
        page = driver.execute_async_script(PLAY, timeline, standard_neutral().tolist())
    assert [state for _, state, _ in page] == states
    for (values, _, delay), (mine, _, my_delay) in zip(expected, page, strict=True):
        np.testing.assert_allclose(mine, values, atol=1e-9)
        assert (delay is None and my_delay is None) or abs(delay - my_delay) < 1e-12


ASK = """
const [packets, secret, rig, done] = [arguments[0], arguments[1], arguments[2], arguments[arguments.length - 1]];
(async () => {
const key = await toonWire.streamKey(Uint8Array.from(secret)), asked = [];
const stream = new toonFaceStream.FaceStream(new toonRig.Rig(rig), null, () => asked.push(now), key);
let now = 0;
packets.forEach((packet, i) => { now = i / 60; stream.feed(new Uint8Array(packet), now); });
done(asked);
})().catch((e) => done({error: String(e)}));
"""


@pytest.mark.slow
def test_the_page_asks_a_stream_that_never_opens_for_keyframes_less_and_less_often():
    """Issue 70: a page with a wrong key asked for a keyframe four times a second for ever."""
    from toon import FaceRig, load_face
    from toon.web_rig import web_rig
    from toonface.room.server import Rooms
    from toonface.room.threaded import in_thread

    writer = StreamWriter(RATE, frames_per_packet=1, key=b"another secret of enough length!", stream=7)
    packets = [list(p) for i, row in enumerate(smooth_motion(600, 0)) if (p := writer.push(row, i / RATE))]
    tokens = {"demo": ("perform-secret-0123456789", "watch-secret-0123456789")}
    with in_thread(Rooms(tokens)) as base, chromium() as driver:
        driver.get(f"{base.replace('ws://', 'http://')}/r/demo")  # a page of the server's: its scripts, noble's
        driver.set_script_timeout(60)
        asked = driver.execute_async_script(ASK, packets, list(b"a shared secret of the room 0123"),
                                            web_rig(FaceRig(load_face("classic"))))
    assert isinstance(asked, list), asked
    # 0.25, 0.5, 1 s apart, then every 2 s over ten seconds: 7 at most, where it was one every 0.25 s (40)
    assert 4 <= len(asked) <= 7 and np.diff(asked)[-1] == pytest.approx(2.0, abs=0.02)
