"""OpenSeeFace in: its tracker's UDP packets (``facetracker.py``, port 11573 by default) as a live
source.

A datagram holds one record of :data:`RECORD_SIZE` bytes per tracked face, in native byte order
with no padding, as ``facetracker.py`` packs it:

====== ===== =============================================================================
offset bytes field
====== ===== =============================================================================
0      8     capture time (double, Unix seconds)
8      4     face id (int32)
12     8     image width, height (2 float32)
20     8     eye openness right, left (float32, about 1 open, 0 shut)
28     1     success (uint8: the 3-D fit worked)
29     4     fit error (float32)
33     16    rotation quaternion (4 float32: the 3-D fit's matrix, in the tracker's own formula)
49     12    Euler angles (3 float32)
61     12    translation (3 float32)
73     272   68 landmark confidences (float32)
345    544   68 landmarks (x, y) in pixels (float32 pairs)
889    840   70 points (x, -y, -z) in the face model's frame: 66 landmarks, the pupils, the
             eyeball centres (float32 triples)
1729   56    14 features (float32): eye_l, eye_r, eyebrow_steepness_l, eyebrow_updown_l,
             eyebrow_quirk_l, eyebrow_steepness_r, eyebrow_updown_r, eyebrow_quirk_r,
             mouth_corner_updown_l, mouth_corner_inout_l, mouth_corner_updown_r,
             mouth_corner_inout_r, mouth_open, mouth_wide
====== ===== =============================================================================

The tracker fits its face model with OpenCV's ``solvePnP`` on landmarks written (row, column),
and its model's x points to the face's right: :func:`head_rotation` turns the quaternion into the
head frame's turn. The features (each 0 at the performer's rest, about -1..1) become ARKit
scores (:func:`arkit_scores`), the gaze comes from the pupils and the eyeball centres, and the
frame carries the landmarks' mean confidence; a record whose fit failed is a lost frame. The
``arkit`` mapping maps it, as it maps VMC and markerless takes.
"""

from __future__ import annotations

import struct
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field

import numpy as np

from capture.blendshapes import BLENDSHAPES
from capture.listening import address_of, datagrams, head_references, listen, lost, posed
from capture.sources import Frame, Source
from capture.vmc import quaternion_matrix

#: OpenSeeFace's usual port.
OSF_PORT = 11573
#: Bytes of one face's record.
RECORD_SIZE = 1785
FEATURES = ("eye_l", "eye_r", "eyebrow_steepness_l", "eyebrow_updown_l", "eyebrow_quirk_l", "eyebrow_steepness_r",
            "eyebrow_updown_r", "eyebrow_quirk_r", "mouth_corner_updown_l", "mouth_corner_inout_l",
            "mouth_corner_updown_r", "mouth_corner_inout_r", "mouth_open", "mouth_wide")
_HEAD = struct.Struct("=diffffBf4f3f3f")
#: The tracker's camera axes (row down, column right, depth away) in head-frame axes seen from the
#: front (x to the performer's left, y up, z toward the camera), and its model's mirror (x to the
#: face's right): the head's turn is ``CAMERA.T @ R @ MIRROR``.
CAMERA = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, -1.0]])
MIRROR = np.diag([-1.0, 1.0, 1.0])
#: Degrees of gaze that make a whole eyeLook score.
GAZE_DEGREES = 30.0


@dataclass
class OsfFace:
    """One face's record (see the module docstring); arrays are float64."""

    time: float
    id: int
    size: tuple[float, float]
    eye_open: tuple[float, float]  # right, left
    success: bool
    fit_error: float
    quaternion: np.ndarray  # (4,)
    euler: np.ndarray  # (3,)
    translation: np.ndarray  # (3,)
    confidence: np.ndarray  # (68,)
    landmarks: np.ndarray  # (68, 2)
    points: np.ndarray  # (70, 3)
    features: dict[str, float] = field(default_factory=dict)


def parse_packet(data: bytes) -> list[OsfFace]:
    """Every face record of one datagram.

    Raises
    ------
    ValueError
        A datagram that is not whole records, or a record with values that are not finite.
    """
    if not data or len(data) % RECORD_SIZE:
        raise ValueError(f"{len(data)} bytes: not a whole number of {RECORD_SIZE}-byte face records")
    faces = []
    for start in range(0, len(data), RECORD_SIZE):
        record = data[start:start + RECORD_SIZE]
        head = _HEAD.unpack_from(record, 0)
        rest = np.frombuffer(record, dtype="=f4", offset=_HEAD.size).astype(float)
        if not (np.isfinite(head[2:]).all() and np.isfinite(rest).all()):
            raise ValueError("a face record with values that are not numbers")
        faces.append(OsfFace(time=head[0], id=head[1], size=(head[2], head[3]), eye_open=(head[4], head[5]),
                             success=bool(head[6]), fit_error=head[7], quaternion=np.array(head[8:12]),
                             euler=np.array(head[12:15]), translation=np.array(head[15:18]),
                             confidence=rest[:68], landmarks=rest[68:204].reshape(68, 2),
                             points=rest[204:414].reshape(70, 3), features=dict(zip(FEATURES, rest[414:428],
                                                                                     strict=True))))
    return faces


def head_rotation(quaternion: np.ndarray) -> np.ndarray:
    """The head's turn ``(3, 3)`` in head-frame axes from the tracker's quaternion (its formula
    gives the transposed matrix's quaternion, so the fit's matrix is the transpose)."""
    fit = quaternion_matrix(*quaternion).T
    return CAMERA.T @ fit @ MIRROR


def arkit_scores(face: OsfFace) -> np.ndarray:
    """ARKit's 51 scores ``(51,)`` from the features and the gaze (0 for those it has no word on)."""
    f = face.features
    up = lambda v: min(max(v, 0.0), 1.0)  # noqa: E731 - one rule for every score
    down = lambda v: min(max(-v, 0.0), 1.0)  # noqa: E731
    scores = {
        "eyeBlinkLeft": down(f["eye_l"]), "eyeWideLeft": up(f["eye_l"]),
        "eyeBlinkRight": down(f["eye_r"]), "eyeWideRight": up(f["eye_r"]),
        "browOuterUpLeft": up(f["eyebrow_updown_l"]), "browDownLeft": down(f["eyebrow_updown_l"]),
        "browOuterUpRight": up(f["eyebrow_updown_r"]), "browDownRight": down(f["eyebrow_updown_r"]),
        "browInnerUp": up((f["eyebrow_updown_l"] + f["eyebrow_updown_r"]) / 2),
        "mouthSmileLeft": up(f["mouth_corner_updown_l"]), "mouthFrownLeft": down(f["mouth_corner_updown_l"]),
        "mouthSmileRight": up(f["mouth_corner_updown_r"]), "mouthFrownRight": down(f["mouth_corner_updown_r"]),
        "mouthStretchLeft": up(max(f["mouth_corner_inout_l"], f["mouth_wide"])),
        "mouthStretchRight": up(max(f["mouth_corner_inout_r"], f["mouth_wide"])),
        "mouthPucker": down(f["mouth_wide"]), "jawOpen": up(f["mouth_open"]),
    }
    # the gaze: each pupil from its eyeball's centre, in the model frame as sent (x to the face's
    # right, y down, z into the face); rightward is outward for the right eye
    for side, pupil, centre in (("Right", 66, 68), ("Left", 67, 69)):
        gaze = face.points[pupil] - face.points[centre]
        depth = max(-gaze[2], 1e-9)  # the pupil lies toward the camera from the centre: -z as sent
        across = np.degrees(np.arctan2(gaze[0], depth)) / GAZE_DEGREES
        rise = np.degrees(np.arctan2(-gaze[1], depth)) / GAZE_DEGREES
        outward = across if side == "Right" else -across
        scores[f"eyeLookOut{side}"], scores[f"eyeLookIn{side}"] = up(outward), down(outward)
        scores[f"eyeLookUp{side}"], scores[f"eyeLookDown{side}"] = up(rise), down(rise)
    return np.array([scores.get(name, 0.0) for name in BLENDSHAPES])


def openseeface_source(target: str, clock: Callable[[], float] = time.perf_counter, timeout: float = 0.5,
                       **_: object) -> Source:
    """A live source of OpenSeeFace's packets, listening on ``target`` (``HOST:PORT``; loopback
    and 11573 by default); the lowest face id in each packet is the performer."""
    sock = listen(target, OSF_PORT, "OpenSeeFace", timeout)
    labels, rest = head_references()
    counts = {"frames": 0, "bad_packets": 0, "lost": 0}
    halt = threading.Event()
    meta: dict = {"mapping": "arkit", "address": address_of(sock), "counts": counts, "rest": rest}

    def frames() -> Iterator[Frame]:
        start = clock()
        for datagram in datagrams(sock, halt):
            try:
                face = min(parse_packet(datagram), key=lambda f: f.id)
                turn = head_rotation(face.quaternion) if face.success else None
            except ValueError:
                counts["bad_packets"] += 1
                continue
            counts["frames"] += 1
            counts["lost"] += turn is None
            yield (lost(clock() - start, rest) if turn is None
                   else posed(clock() - start, rest, turn, arkit_scores(face), float(face.confidence.mean())))

    return Source(labels, 30.0, frames(), f"OpenSeeFace on {meta['address']}", live=True, meta=meta,
                  channel_names=BLENDSHAPES, halt=halt, release=sock.close)
