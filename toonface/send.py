"""The telepresence sender: a performer source in real time -> live mapping -> motor sinks.

A source (:mod:`capture.sources`: a take file, a dot-marker video tracked as it plays, the
synthetic performer) plays on the wall clock; each frame is cleaned and mapped in its live form
(:class:`mapping.stepwise.LiveMapper`) and written, stamped with its capture time, to every motor
sink: the stream sender (:class:`stream.sender.StreamSender`: only motor values cross the
network), and a recording if asked.
"""

from __future__ import annotations

import threading
import time
from collections import deque
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

from capture import MarkerSet, Take
from capture.sources import Source, paced
from common import InputError
from mapping import Mapping, Profile, calibrate, choose_mapping, prepare
from mapping.life import LiveLife
from mapping.live_gaps import REGRESS_SECONDS
from mapping.settings import HOLD_SECONDS
from mapping.stepwise import LiveMapper
from mapping.take_notes import solver_note
from mapping.typical import typical_profile
from mapping.workflow import SELF_MIN_SIDE, check_profile
from toon.recording import LatestMotors, MotorSink

#: Seconds of a take its own profile is calibrated on, when its marker set has no typical one.
CALIBRATION_SECONDS = 10.0
#: Seconds a live source with no profile (a camera) learns its ranges for, after its rest.
LEARN_SECONDS = 60.0


def build_mapper(source: Source, mapping: Mapping | str | None = None, profile: Profile | None = None,
                 target_neutral: np.ndarray | None = None, rest_seconds: float = 1.0,
                 notes: list[str] | None = None, life: bool | None = None, regress_seconds: float = REGRESS_SECONDS,
                 hold_seconds: float = HOLD_SECONDS) -> LiveMapper:
    """The live mapper for a source: the named mapping (or the one the source names, or the preset
    its labels match), and the given profile or the marker set's typical one, with the rest taken
    from the first ``rest_seconds``. Where the marker set has no typical profile, a take's own first
    :data:`CALIBRATION_SECONDS` make one; what was chosen is appended to ``notes``. ``life``: the
    life layer (:mod:`mapping.life`) on the motors the mapping does not drive or loses (None: on
    for a voice alone, as offline). A lost marker is regressed on those seen for up to
    ``regress_seconds``, or held for up to ``hold_seconds`` where it is not regressed (a ``pair``
    rule's, and a blendshape channel), never longer than ``regress_seconds``
    (:mod:`mapping.live_gaps`)."""
    if notes is not None and source.meta.get("note"):
        notes.append(source.meta["note"])  # how the source read what it was given
    mapping = mapping or source.meta.get("mapping")  # a bridge names the mapping its data needs
    rest_seconds = source.meta.get("rest_seconds", rest_seconds)  # a voice knows its rest: silence
    probe_take = Take(np.zeros((1, len(source.labels), 3)), source.labels, source.rate,
                      channels=np.zeros((1, len(source.channel_names))), channel_names=source.channel_names)
    chosen, markerset = choose_mapping(probe_take, mapping)
    if notes is not None and (left_out := chosen.left_out_note()) is not None:
        notes.append(left_out)
    profile = profile or typical_profile(markerset.name)
    learn = 0.0
    if profile is None and not any(rule.normalise == "profile" for rule in chosen.rules):
        profile = Profile(markerset.name, {}, np.eye(3))  # scores, degrees: no performer's range to measure
        if notes is not None:
            notes.append(f"mapping {chosen.name} reads no performer's ranges: "
                         + (f"rest from the first {rest_seconds:g} s" if rest_seconds else "its rest is silence"))
    elif profile is None and source.recording is None:  # a camera: rest from its first second, ranges as it runs
        profile, learn = Profile(markerset.name, {}, np.eye(3)), LEARN_SECONDS
        if notes is not None:
            notes.append(f"no profile for marker set {markerset.name}: rest from the first {rest_seconds:g} s, "
                         f"ranges learned over the next {LEARN_SECONDS:g} s")
    elif profile is None:
        assert source.recording is not None
        profile = _own_profile(source.recording, chosen, markerset)
        if notes is not None:
            notes.append(f"no typical profile for marker set {markerset.name}: a profile from the take's "
                         f"first {CALIBRATION_SECONDS:g} s (rest {profile.notes['neutral']}, ranges "
                         f"{profile.notes['range']})")
    check_profile(profile, chosen, markerset.name)
    if notes is not None:
        notes.extend(filter(None, [solver_note(profile, chosen)]))
    try:
        mapper = LiveMapper(chosen, markerset, profile, source.labels, source.rate, target_neutral, rest_seconds,
                            hold_seconds=min(hold_seconds, regress_seconds), learn_seconds=learn,
                            channel_names=source.channel_names, regress_seconds=regress_seconds)
    except ValueError as exc:
        raise InputError(str(exc)) from None
    if notes is not None and not mapper.own_shape and rest_seconds <= 0:
        notes.append(f"profile {profile.source or profile.performer or markerset.name} holds no head-reference shape "
                     f"and no rest is taken: the head is fitted on marker set {markerset.name}'s shape (calibrate "
                     "again to keep the performer's)")
    if life is None:
        life = source.meta.get("source") == "voice"
    if life:
        mapper.life = LiveLife(mapper.neutral, source.rate, {rule.code for rule in chosen.rules})
        if notes is not None:
            notes.append("the life layer moves what the mapping does not drive, or loses: blinks, gaze, "
                         "brows and head" + (" from the voice's pauses, pitch and stress" if "sound_level" in
                                             source.channel_names else ""))
    return mapper


def _own_profile(take: Take, mapping: Mapping, markerset: MarkerSet) -> Profile:
    """A profile from the take's first seconds: rest from its first second (or stillest), ranges
    from all of them, as ``map`` makes one for a take without a profile."""
    first = take.window(float(take.times[0]), float(take.times[0]) + CALIBRATION_SECONDS)
    start = Take(take.positions[first], take.labels, take.rate, take.times[first] - take.times[0], take.dims,
                 take.meta, take.channels[first], take.channel_names)
    return calibrate(mapping, prepare(start, markerset), percentiles=(1.0, 99.0), min_side=SELF_MIN_SIDE)


@dataclass
class SendReport:
    """What a sender did: frames mapped and the mapping's cost per frame (the last minute at 60 Hz)."""

    frames: int = 0
    step_seconds: deque[float] = field(default_factory=lambda: deque(maxlen=3600))

    def cost(self) -> dict:
        """The mapping's recent cost per frame, ms (median and 95th percentile)."""
        steps = np.array(self.step_seconds or [0.0]) * 1000
        return {"map_ms_median": round(float(np.median(steps)), 3),
                "map_ms_p95": round(float(np.percentile(steps, 95)), 3)}


def run_sender(source: Source, mapper: LiveMapper, sinks: Sequence[MotorSink], seconds: float | None = None,
               clock: Callable[[], float] = time.perf_counter, sleep: Callable[[float], None] = time.sleep,
               stop: Callable[[], bool] = lambda: False, report: SendReport | None = None) -> SendReport:
    """Play ``source`` in real time, map each frame and write it to every sink; returns what was
    done (in ``report`` where given, so that a caller interrupted has what was done so far). The
    mapper sees the source's own times; the sinks see stream time (frame n at n / rate), so that
    a recording lines up with the stream frame for frame. A live source is halted after
    ``seconds`` of wall time even when no frame comes (a network bridge nobody sends to). The
    sinks stay open (the caller closes them)."""
    report = SendReport() if report is None else report
    timer = None
    if seconds is not None and source.live:
        timer = threading.Timer(seconds, source.halt.set)
        timer.daemon = True
        timer.start()
    try:
        _send_frames(source, mapper, sinks, seconds, clock, sleep, stop, report)
    finally:
        if timer is not None:
            timer.cancel()
    return report


def _send_frames(source: Source, mapper: LiveMapper, sinks: Sequence[MotorSink], seconds: float | None,
                 clock: Callable[[], float], sleep: Callable[[float], None], stop: Callable[[], bool],
                 report: SendReport) -> None:
    for frame in paced(source, clock, sleep):
        if (seconds is not None and frame.t >= seconds - 0.5 / source.rate) or stop():
            break
        began = clock()  # a camera's grab, where it says when (before tracking took its tens of ms), else now
        captured = source.meta["clock_start"] + frame.t if "clock_start" in source.meta else began
        values, confidence = mapper.step_frame(frame)
        report.step_seconds.append(clock() - began)
        extra = mapper.extra_values() or None  # the parameters beyond the 21 (HT...), where the mapping drives any
        for sink in sinks:  # stream time: frame n at n / rate, as the wire carries it (a camera's stamps jitter)
            sink.write(report.frames / source.rate, values, captured, confidence, extra=extra)
        report.frames += 1


class Follower:
    """A performer source mapped live in a background thread, its newest motors always at hand
    (``play --source``): the thread plays the source in real time and writes each frame to
    :attr:`latest`; :meth:`stop` ends it."""

    def __init__(self, source: Source, mapper: LiveMapper, neutral: np.ndarray) -> None:
        self.source, self.mapper = source, mapper
        self.latest = LatestMotors(neutral)
        self.error: BaseException | None = None
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)

    @classmethod
    def open(cls, spec: str, neutral: np.ndarray, say: Callable[[str], None] = lambda _: None,
             repeat: bool = False, eye_contact: bool = False, life: bool | None = None,
             regress_seconds: float = REGRESS_SECONDS, hold_seconds: float = HOLD_SECONDS) -> Follower:
        """The follower of the source ``spec`` names (as ``send`` takes it; a file played again and
        again with ``repeat``), mapped onto a face whose neutral is ``neutral``; the choices made are
        said through ``say``; ``eye_contact``: calibrated in the second after the rest
        (:mod:`mapping.eye_contact`); ``life``, ``regress_seconds`` and ``hold_seconds``: as
        :func:`build_mapper` takes them."""
        from capture.sources import open_source
        from mapping.eye_contact import LiveEyeContact

        source = open_source(spec, repeat=repeat)
        notes: list[str] = []
        mapper = build_mapper(source, target_neutral=neutral, notes=notes, life=life, regress_seconds=regress_seconds,
                              hold_seconds=hold_seconds)
        for note in notes:
            say(f"note: {note}")
        if eye_contact:
            mapper.eye_contact = LiveEyeContact(neutral, after=0.0, say=lambda text: say(f"note: {text}"))
        return cls(source, mapper, neutral)

    def start(self) -> None:
        """Begin following."""
        self._thread.start()

    def stop(self) -> None:
        """Stop following and wait for the thread (a bridge waiting for data is told to end)."""
        self._stop.set()
        self.source.halt.set()
        if self._thread.is_alive():
            self._thread.join(timeout=5.0)

    def _run(self) -> None:
        try:
            run_sender(self.source, self.mapper, [self.latest], stop=self._stop.is_set)
        except Exception as exc:  # noqa: BLE001 - kept for the caller; the face holds its last frame
            self.error = exc
