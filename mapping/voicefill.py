"""A voice fills the mouth where the face is lost: a talking-head video whose face turns away,
leaves the frame or is covered still has its sound, and the sound knows when the mouth opens.

Per mouth motor, a frame is lost where any marker its rule reads is unseen in the take (before
any gap filling: a filled gap is a guess, the voice is a measurement). There the motor takes the
voice's value (the voice mapped onto the same face), crossfaded over :data:`FADE_S` either side so that the mouth
never jumps between the two.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from capture.markerset import MarkerSet
from capture.take import Take
from mapping.mapfile import Mapping
from toon.motors import MOTOR_CODES
from toon.track import MotorTrack

#: The motors a voice moves (the voice mapping's): the jaw and the corners.
MOUTH = ("MB", "MLH", "MLV", "MRH", "MRV")
#: The crossfade between face and voice at each edge of a lost stretch (s).
FADE_S = 0.1


def lost_mouth(take: Take, mapping: Mapping, markerset: MarkerSet, codes: tuple[str, ...] = MOUTH) -> np.ndarray:
    """Where each of ``codes`` has lost a marker its rule reads, ``(frames, len(codes))`` bool
    (never, for a motor whose rule reads no markers)."""
    found = markerset.match(take.labels)
    seen = np.isfinite(take.positions).all(axis=2)
    lost = np.zeros((take.frames, len(codes)), bool)
    rules = {rule.code: rule for rule in mapping.rules}
    for k, code in enumerate(codes):
        rule = rules.get(code)
        markers = {m for source in rule.sources for m in source.markers} if rule is not None else set()
        columns = [take.index(found[m]) for m in sorted(markers) if m in found]
        if columns:
            lost[:, k] = ~seen[:, columns].all(axis=1)
    return lost


def fill_from_voice(track: MotorTrack, lost: np.ndarray, voice: MotorTrack, voice_times: np.ndarray,
                    codes: tuple[str, ...] = MOUTH) -> tuple[MotorTrack, int]:
    """``track`` with ``codes`` taken from ``voice`` where ``lost`` ``(frames, len(codes))``,
    crossfaded over :data:`FADE_S` either side (the voice's share falls linearly with the
    distance to the nearest lost frame); the voice's values ``(n, 21)`` at ``voice_times``
    ``(n,)`` (seconds on the track's clock), held at its ends, as the voice mapping places them on
    this face (matching the face's own spread where both are seen was tried: where the face is
    seen only in silence it blew the voice up to the limits). Returns the track and how many
    frames took any of the voice."""
    from scipy.ndimage import distance_transform_edt

    times = track.times
    fade = FADE_S * track.rate
    values = np.array(track.values, dtype=float)
    used = np.zeros(track.frames, bool)
    for k, code in enumerate(codes):
        if not lost[:, k].any():
            continue
        column = MOTOR_CODES.index(code)
        weight = np.clip(1.0 - distance_transform_edt(~lost[:, k]) / (fade + 1.0), 0.0, 1.0)
        heard = np.interp(times, voice_times, voice.values[:, column])
        values[:, column] = (1.0 - weight) * values[:, column] + weight * heard
        used |= weight > 0
    filled = int(used.sum())
    return replace(track, values=values, meta={**track.meta, "voice_filled_frames": filled}), filled
