"""The VMC protocol out: the motors a player shows, sent as VMC messages (OSC over UDP) so that
other apps (VTuber software, an avatar in a game engine) can be driven by toonface's tracking or
animations.

Each frame is one or more OSC bundles (each under :data:`MAX_BUNDLE` bytes) holding:

- ``/VMC/Ext/Blend/Val (name) (value)`` for the 21 motors, named by their codes (``MB``...), 0..1;
- the same for the ARKit blendshapes that one motor gives cleanly (:data:`ARKIT_OUT`): the motor's
  way from the face's neutral to one end of its range as a score 0..1 (``jawOpen`` is MB's way
  open, ``eyeBlinkLeft`` ELU's way shut, ``eyeWideLeft`` its way up);
- the parameters beyond the 21 where a frame has them, by their codes (``HT``...), and as the
  ARKit scores that stand for them (:func:`extra_scores`: ``cheekPuff``, ``jawLeft``/``jawRight``,
  ``noseSneerLeft``/``Right``);
- ``/VMC/Ext/Bone/Pos "Head" 0 0 0 (qx qy qz qw)``: HH and HV as the head's turn, in Unity's
  left-handed axes as a VMC receiver reads it, :data:`HEAD_DEGREES` a motor unit from neutral
  (as the mapping presets read the head), and HT as its roll, :data:`TILT_DEGREES` a unit;
- ``/VMC/Ext/Blend/Apply``, last: the set is complete.
"""

from __future__ import annotations

import math
import socket
from collections.abc import Mapping

import numpy as np

from toon import MOTOR_CODES

#: Degrees of head turn per motor unit of HH and HV from neutral (the presets' ``scale``).
HEAD_DEGREES = 60.0
#: Degrees of head roll per unit of HT from its rest (the presets' ``scale``).
TILT_DEGREES = 50.0
#: The largest bundle sent (a typical Ethernet datagram's payload, less headers).
MAX_BUNDLE = 1400
#: ARKit blendshapes one motor gives: (name, motor, way) with way +1 toward the motor's 1, -1 toward 0.
ARKIT_OUT: tuple[tuple[str, str, int], ...] = (
    ("jawOpen", "MB", 1),
    ("eyeBlinkRight", "ERU", -1), ("eyeWideRight", "ERU", 1), ("eyeBlinkLeft", "ELU", -1), ("eyeWideLeft", "ELU", 1),
    ("eyeSquintRight", "ERL", 1), ("eyeSquintLeft", "ELL", 1),
    ("browOuterUpRight", "BRL", 1), ("browDownRight", "BRM", -1),
    ("browOuterUpLeft", "BLL", 1), ("browDownLeft", "BLM", -1),
    ("eyeLookInRight", "PRH", 1), ("eyeLookOutRight", "PRH", -1),
    ("eyeLookUpRight", "PRV", 1), ("eyeLookDownRight", "PRV", -1),
    ("eyeLookOutLeft", "PLH", 1), ("eyeLookInLeft", "PLH", -1),
    ("eyeLookUpLeft", "PLV", 1), ("eyeLookDownLeft", "PLV", -1),
    ("mouthSmileRight", "MRV", 1), ("mouthFrownRight", "MRV", -1),
    ("mouthSmileLeft", "MLV", 1), ("mouthFrownLeft", "MLV", -1),
    ("mouthStretchRight", "MRH", 1), ("mouthStretchLeft", "MLH", 1),
)
_INDEX = {code: i for i, code in enumerate(MOTOR_CODES)}


def arkit_scores(values: np.ndarray, neutral: np.ndarray) -> dict[str, float]:
    """The ARKit scores of :data:`ARKIT_OUT` for motors ``values`` ``(21,)`` on a face whose
    neutral is ``neutral`` ``(21,)``: each the fraction of the way from neutral to that end."""
    out = {}
    for name, code, way in ARKIT_OUT:
        v, n = float(values[_INDEX[code]]), float(neutral[_INDEX[code]])
        room = (1.0 - n) if way > 0 else n
        out[name] = min(max(way * (v - n) / room, 0.0), 1.0) if room > 1e-9 else 0.0
    out["browInnerUp"] = min(max(((values[_INDEX["BRM"]] - neutral[_INDEX["BRM"]])
                                  + (values[_INDEX["BLM"]] - neutral[_INDEX["BLM"]]))
                                 / max(2.0 - neutral[_INDEX["BRM"]] - neutral[_INDEX["BLM"]], 1e-9), 0.0), 1.0)
    return out


def extra_scores(extra: Mapping[str, float]) -> dict[str, float]:
    """The ARKit scores that stand for the standard parameters beyond the 21 in ``extra``, as the
    arkit preset reads them back: CP is ``cheekPuff``; JS the ``jawLeft`` or ``jawRight`` of its
    way from 0.5; UL both ``noseSneer`` scores."""
    out = {}
    if "CP" in extra:
        out["cheekPuff"] = float(extra["CP"])
    if "JS" in extra:
        side = 2.0 * (float(extra["JS"]) - 0.5)
        out["jawLeft"], out["jawRight"] = max(side, 0.0), max(-side, 0.0)
    if "UL" in extra:
        out["noseSneerLeft"] = out["noseSneerRight"] = float(extra["UL"])
    return out


def head_quaternion(values: np.ndarray, neutral: np.ndarray, degrees: float = HEAD_DEGREES, tilt: float = 0.5
                    ) -> tuple[float, float, float, float]:
    """The head's turn (x, y, z, w) in Unity's left-handed axes: yaw toward the performer's
    left is a turn about -y there, a raised chin a turn about -x, and ``tilt`` (HT, 0.5
    upright) a roll about z, counter-clockwise as the camera sees it toward 1."""
    yaw = math.radians((values[_INDEX["HH"]] - neutral[_INDEX["HH"]]) * degrees)
    pitch = math.radians((values[_INDEX["HV"]] - neutral[_INDEX["HV"]]) * degrees)
    roll = math.radians((tilt - 0.5) * TILT_DEGREES)
    # Unity's R = Ry(-yaw) Rx(-pitch) Rz(-roll): the quaternion product q_y * q_x * q_z
    ay, ax, az = -yaw / 2, -pitch / 2, -roll / 2
    qx = (math.cos(ay) * math.sin(ax), math.sin(ay) * math.cos(ax), -math.sin(ay) * math.sin(ax),
          math.cos(ay) * math.cos(ax))
    x, y, z, w = qx
    cz, sz = math.cos(az), math.sin(az)  # times (0, 0, sin, cos)
    return (x * cz + y * sz, y * cz - x * sz, z * cz + w * sz, w * cz - z * sz)


class VmcOut:
    """A motor sink sending each frame to a VMC receiver at ``address``.

    Parameters
    ----------
    address : tuple of (str, int)
    neutral : ndarray, shape (21,)
        The face's neutral: where the blendshape scores and the head turn start.
    """

    def __init__(self, address: tuple[str, int], neutral: np.ndarray) -> None:
        self.address = address
        self.neutral = np.asarray(neutral, dtype=float)
        self.frames = 0
        self.bytes = 0
        self._sock = socket.socket(socket.AF_INET6 if ":" in address[0] else socket.AF_INET, socket.SOCK_DGRAM)

    def datagrams(self, values: np.ndarray, extra: Mapping[str, float] | None = None) -> list[bytes]:
        """One frame's bundles, in order, the Apply last (``extra``: its parameters beyond the 21)."""
        from pythonosc.osc_bundle_builder import IMMEDIATELY, OscBundleBuilder
        from pythonosc.osc_message import OscMessage
        from pythonosc.osc_message_builder import OscMessageBuilder

        def message(address: str, *args: str | float) -> OscMessage:
            built = OscMessageBuilder(address)
            for arg in args:
                built.add_arg(arg)
            return built.build()

        messages = [message("/VMC/Ext/Blend/Val", code, float(values[i])) for i, code in enumerate(MOTOR_CODES)]
        messages += [message("/VMC/Ext/Blend/Val", name, score)
                     for name, score in arkit_scores(values, self.neutral).items()]
        extra = dict(extra or {})
        messages += [message("/VMC/Ext/Blend/Val", code, float(v)) for code, v in extra.items()]
        messages += [message("/VMC/Ext/Blend/Val", name, score) for name, score in extra_scores(extra).items()]
        messages.append(message("/VMC/Ext/Bone/Pos", "Head", 0.0, 0.0, 0.0,
                                *head_quaternion(values, self.neutral, tilt=extra.get("HT", 0.5))))
        messages.append(message("/VMC/Ext/Blend/Apply"))
        out, bundle, size = [], OscBundleBuilder(IMMEDIATELY), 16
        for m in messages:
            if size + len(m.dgram) + 4 > MAX_BUNDLE:
                out.append(bundle.build().dgram)
                bundle, size = OscBundleBuilder(IMMEDIATELY), 16
            bundle.add_content(m)
            size += len(m.dgram) + 4
        out.append(bundle.build().dgram)
        return out

    def write(self, t: float, values: np.ndarray, captured: float | None = None,
              confidence: np.ndarray | None = None, extra: Mapping[str, float] | None = None) -> None:
        """Send one frame and its parameters beyond the 21 (a receiver that is not there costs
        nothing: UDP)."""
        for datagram in self.datagrams(np.clip(np.asarray(values, dtype=float), 0.0, 1.0), extra):
            try:
                self._sock.sendto(datagram, self.address)
            except OSError:  # nobody listening (ICMP refused on loopback): the next frame tries again
                continue
            self.bytes += len(datagram)
        self.frames += 1

    def close(self) -> None:
        self._sock.close()

    def abort(self) -> None:
        self._sock.close()
