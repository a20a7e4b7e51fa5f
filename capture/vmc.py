"""The VMC protocol in: a face-tracking app's blendshapes and head, received as a live source.

VMC (Virtual Motion Capture protocol) is OSC over UDP, as phone face-tracking apps and VTuber
software send it (port 39539 by default). What this source reads:

``/VMC/Ext/Blend/Val (string name) (float value)``
    A blendshape's value, 0..1, held until ``/VMC/Ext/Blend/Apply`` makes the set current.
    Names are ARKit's (``jawOpen``, ``eyeBlinkLeft``; also written ``JawOpen`` or
    ``eyeBlink_L``) or VRM's expression presets (``A``/``aa``, ``Blink_L``/``blinkLeft``,
    ``Joy``/``happy``...), which :data:`VRM_AS_ARKIT` turns into ARKit's; other names are
    counted and ignored.
``/VMC/Ext/Bone/Pos (string name) (float px py pz) (float qx qy qz qw)``
    A bone's local pose in Unity's left-handed axes (x right, y up, z forward): the ``Head``
    (after the ``Neck``, where one is sent) turns the head.
``/VMC/Ext/OK (int loaded) [(int calibration state) (int calibration mode) (int tracking)]``
    A tracking status of 0 means the performer is lost: frames carry no values until it is back.

A frame is made at each ``Apply`` (or, from a sender that sends only bones, at each datagram
with a head). Its channels are the 51 ARKit scores of :data:`capture.blendshapes.BLENDSHAPES`
(0 for a name not yet sent once any set was applied), and its positions the head reference
points of the ``face`` marker set turned by the head's rotation, so that the mapping finds the
head turn as it finds a tracked face's (``head`` sources); a sender of blendshapes alone holds
the head still. The built-in ``arkit`` mapping reads
these channels and serves a markerless take's as well.
"""

from __future__ import annotations

import math
import re
import threading
import time
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass, field

import numpy as np

from capture.blendshapes import BLENDSHAPES
from capture.listening import address_of, datagrams, head_references, listen, lost, posed
from capture.sources import Frame, Source

#: VMC's usual port.
VMC_PORT = 39539
#: At most this many sent names are remembered with what they mean.
KNOWN_NAMES = 1024
#: VRM's expression presets (0.x and 1.0 names) as ARKit blendshapes: each preset's value times
#: these weights; a channel fed by several takes the largest.
VRM_AS_ARKIT: dict[str, dict[str, float]] = {
    "a": {"jawOpen": 1.0}, "aa": {"jawOpen": 1.0},
    "i": {"jawOpen": 0.3, "mouthStretchLeft": 0.5, "mouthStretchRight": 0.5},
    "ih": {"jawOpen": 0.3, "mouthStretchLeft": 0.5, "mouthStretchRight": 0.5},
    "u": {"jawOpen": 0.2, "mouthPucker": 1.0}, "ou": {"jawOpen": 0.2, "mouthPucker": 1.0},
    "e": {"jawOpen": 0.5, "mouthStretchLeft": 0.3, "mouthStretchRight": 0.3},
    "ee": {"jawOpen": 0.5, "mouthStretchLeft": 0.3, "mouthStretchRight": 0.3},
    "o": {"jawOpen": 0.7, "mouthFunnel": 0.6}, "oh": {"jawOpen": 0.7, "mouthFunnel": 0.6},
    "blink": {"eyeBlinkLeft": 1.0, "eyeBlinkRight": 1.0},
    "blink_l": {"eyeBlinkLeft": 1.0}, "blinkleft": {"eyeBlinkLeft": 1.0},
    "blink_r": {"eyeBlinkRight": 1.0}, "blinkright": {"eyeBlinkRight": 1.0},
    "joy": {"mouthSmileLeft": 1.0, "mouthSmileRight": 1.0, "cheekSquintLeft": 0.5, "cheekSquintRight": 0.5},
    "happy": {"mouthSmileLeft": 1.0, "mouthSmileRight": 1.0, "cheekSquintLeft": 0.5, "cheekSquintRight": 0.5},
    "angry": {"browDownLeft": 1.0, "browDownRight": 1.0, "mouthFrownLeft": 0.3, "mouthFrownRight": 0.3},
    "sorrow": {"browInnerUp": 1.0, "mouthFrownLeft": 0.8, "mouthFrownRight": 0.8},
    "sad": {"browInnerUp": 1.0, "mouthFrownLeft": 0.8, "mouthFrownRight": 0.8},
    "fun": {"mouthSmileLeft": 0.6, "mouthSmileRight": 0.6, "eyeSquintLeft": 0.4, "eyeSquintRight": 0.4},
    "relaxed": {"mouthSmileLeft": 0.6, "mouthSmileRight": 0.6, "eyeSquintLeft": 0.4, "eyeSquintRight": 0.4},
    "surprised": {"browInnerUp": 1.0, "browOuterUpLeft": 1.0, "browOuterUpRight": 1.0, "eyeWideLeft": 1.0,
                  "eyeWideRight": 1.0, "jawOpen": 0.4},
    "lookup": {"eyeLookUpLeft": 1.0, "eyeLookUpRight": 1.0},
    "lookdown": {"eyeLookDownLeft": 1.0, "eyeLookDownRight": 1.0},
    "lookleft": {"eyeLookOutLeft": 1.0, "eyeLookInRight": 1.0},  # toward the performer's left
    "lookright": {"eyeLookOutRight": 1.0, "eyeLookInLeft": 1.0},
}
#: Unity's left-handed axes (x right, y up, z forward) to the head frame's right-handed ones (x to
#: the performer's left, y up, z out of the face): a rotation R becomes FLIP @ R @ FLIP.
FLIP = np.diag([-1.0, 1.0, 1.0])


def arkit_name(name: str) -> str | None:
    """The ARKit blendshape a sent name means, whatever its case, with ``_L``/``_R`` for
    Left/Right; None for any other name."""
    key = re.sub(r"_([lr])$", lambda m: "left" if m.group(1) == "l" else "right", name.lower())
    return _ARKIT_BY_KEY.get(key)


_ARKIT_BY_KEY = {n.lower(): n for n in BLENDSHAPES}


def quaternion_matrix(x: float, y: float, z: float, w: float) -> np.ndarray:
    """The rotation matrix ``(3, 3)`` of a quaternion (normalised first)."""
    q = np.array([x, y, z, w], dtype=float)
    norm = np.linalg.norm(q)
    if not np.isfinite(norm) or norm < 1e-9:
        raise ValueError("not a rotation")
    x, y, z, w = q / norm
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


@dataclass
class VmcState:
    """What a VMC sender has said so far; :meth:`take` reads one OSC message into it and says
    whether a frame is due.

    Attributes
    ----------
    pending : dict of str to float
        Blendshape values since the last Apply, by the name sent.
    current : ndarray, shape (51,)
        The applied ARKit scores (NaN until a first Apply).
    bones : dict of str to ndarray
        The latest local rotation ``(3, 3)`` of each bone that turns the head (Unity's axes).
    tracking : bool
        False while the sender says its performer is lost.
    counts : dict of str to int
        ``frames``, ``unknown_names`` (blendshapes neither ARKit's nor VRM's), ``bad_messages``.
    """

    pending: dict[str, float] = field(default_factory=dict)
    current: np.ndarray = field(default_factory=lambda: np.full(len(BLENDSHAPES), np.nan))
    bones: dict[str, np.ndarray] = field(default_factory=dict)
    tracking: bool = True
    applied_once: bool = False
    _meaning: dict[str, int | tuple[tuple[int, float], ...]] = field(default_factory=dict, init=False, repr=False)
    counts: dict[str, int] = field(default_factory=lambda: {"frames": 0, "unknown_names": 0, "bad_messages": 0})

    def take(self, address: str, params: Sequence) -> bool:
        """Read one message; True when it completes a frame (an Apply, or a head from a sender
        that never applies blendshapes). A malformed message is counted and ignored."""
        try:
            if address == "/VMC/Ext/Blend/Val":
                name, value = params[0], float(params[1])
                if not isinstance(name, str) or not math.isfinite(value):
                    raise ValueError
                self.pending[name] = min(max(value, 0.0), 1.0)
            elif address == "/VMC/Ext/Blend/Apply":
                self._apply()
                return True
            elif address == "/VMC/Ext/Bone/Pos":
                name = params[0]
                if name in ("Head", "Neck"):
                    self.bones[name] = quaternion_matrix(*(float(v) for v in params[4:8]))
                    return name == "Head" and not self.applied_once
            elif address == "/VMC/Ext/OK" and len(params) >= 4:
                self.tracking = int(params[3]) != 0
        except (ValueError, TypeError, IndexError):
            self.counts["bad_messages"] += 1
        return False

    def _apply(self) -> None:
        if not self.applied_once:
            self.current[:] = 0.0
            self.applied_once = True
        fed: dict[int, float] = {}
        direct: set[int] = set()
        for name, value in self.pending.items():
            meant = self._meaning.get(name)
            if meant is None:  # a sender sends the same names each frame: each is read once
                meant = _meaning_of(name)
                if len(self._meaning) < KNOWN_NAMES:  # not without end, from a sender of ever new names
                    self._meaning[name] = meant
            if isinstance(meant, int):
                self.current[meant] = value
                direct.add(meant)
            elif meant:
                for target, weight in meant:
                    fed[target] = max(fed.get(target, 0.0), weight * value)
            else:
                self.counts["unknown_names"] += 1
        for target, value in fed.items():  # a preset drives its shapes unless the ARKit name came too
            if target not in direct:
                self.current[target] = value
        self.pending.clear()

    def head(self) -> np.ndarray | None:
        """The head's rotation in the head frame's axes ``(3, 3)``: the neck's then the head's
        local turn; None before any head was sent."""
        if "Head" not in self.bones:
            return None
        turn = self.bones.get("Neck", np.eye(3)) @ self.bones["Head"]
        return FLIP @ turn @ FLIP


_INDEX = {name: i for i, name in enumerate(BLENDSHAPES)}


def _meaning_of(name: str) -> int | tuple[tuple[int, float], ...]:
    """What a sent blendshape name sets: an ARKit score's index, a VRM preset's (index, weight)
    pairs, or nothing (an empty tuple) for a name neither knows."""
    arkit = arkit_name(name)
    if arkit is not None:
        return _INDEX[arkit]
    return tuple((_INDEX[target], weight) for target, weight in VRM_AS_ARKIT.get(name.lower(), {}).items())


def osc_messages(datagram: bytes) -> list[tuple[str, list]]:
    """Each OSC message of a datagram (a message, or a bundle of them, nested or not, read by
    python-osc) as its address and arguments, in the order sent; a ValueError where it cannot be
    read. Bundles' time tags are not waited for: a live face wants every message now."""
    from pythonosc.osc_bundle import OscBundle
    from pythonosc.osc_bundle import ParseError as BundleError
    from pythonosc.osc_message import OscMessage
    from pythonosc.osc_message import ParseError as MessageError

    out: list[tuple[str, list]] = []
    try:
        if OscBundle.dgram_is_bundle(datagram):
            pending: list = [OscBundle(datagram)]
            while pending:  # depth first, in the order sent
                content = pending.pop()
                if isinstance(content, OscBundle):
                    pending.extend(reversed(list(content)))
                else:
                    out.append((content.address, content.params))
        else:
            message = OscMessage(datagram)
            out.append((message.address, message.params))
    except (BundleError, MessageError) as exc:
        raise ValueError(f"not an OSC packet: {exc}") from None
    return out


def vmc_source(target: str, clock: Callable[[], float] = time.perf_counter, timeout: float = 0.5,
               **_: object) -> Source:
    """A live source of a VMC sender's frames, listening on ``target`` (``HOST:PORT``; loopback
    and 39539 by default); see :mod:`capture.listening`."""

    sock = listen(target, VMC_PORT, "VMC", timeout)
    labels, rest = head_references()
    state = VmcState()
    halt = threading.Event()
    meta: dict = {"mapping": "arkit", "address": address_of(sock), "counts": state.counts, "rest": rest}

    def frames() -> Iterator[Frame]:
        start = clock()
        for datagram in datagrams(sock, halt):
            try:
                messages = osc_messages(datagram)
            except ValueError:
                state.counts["bad_messages"] += 1
                continue
            due = False
            for address, params in messages:
                due = state.take(address, params) or due
            if due:
                state.counts["frames"] += 1
                # a sender of blendshapes only: a head held still
                yield (posed(clock() - start, rest, state.head(), state.current.copy()) if state.tracking
                       else lost(clock() - start, rest))

    return Source(labels, 60.0, frames(), f"VMC on {meta['address']}", live=True, meta=meta,
                  channel_names=BLENDSHAPES, halt=halt, release=sock.close)
