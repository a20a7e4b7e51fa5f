"""Secondary motion while a face is drawn: its physics drivers (:mod:`toon.physics`) run on what
moves the face, and what they move is added to the parameters drawn.

One rule for every way a face is drawn. Over a track (``render``, ``retarget``, the parts of a
batch, ``play --motors``) the drivers run on the track's own samples, whatever the frame rate:
frames drawn at 30 or at 60 a second, or a part that starts half-way (its drivers run from the
track's start to it), show the same motion at the same instants. Over a live source (a stream, a
followed camera) they run on the frames as they come.
"""

from __future__ import annotations

from collections.abc import Mapping

import numpy as np

from toon import Face, MotorTrack
from toon.motors import MOTOR_CODES, N_MOTORS
from toon.physics import Physics, physics_for

#: Live frames further apart than this (seconds) are a pause, not a motion: the inputs held
#: through it move only in the last GAP before the new frame (about a frame period's ramp).
GAP = 1 / 30


class SecondaryMotion:
    """A face's drivers over a track's samples (``track``) or over live frames (none).

    Parameters
    ----------
    face : Face
    track : MotorTrack, optional
        The track whose samples drive the physics; without it, each frame asked about does.
    """

    def __init__(self, face: Face, track: MotorTrack | None = None) -> None:
        self.codes = (*MOTOR_CODES, *face.extra_codes)
        rests = face.extra_neutral()
        self.rests = {**{c: float(v) for c, v in zip(MOTOR_CODES, face.neutral(), strict=True)}, **rests}
        self.physics: Physics | None = physics_for(face.physics, self.codes, self.rests)
        self._rows = self._track_rows(track) if track is not None and self.physics is not None else None
        self._times = track.times if track is not None else None  # made once: each frame asks
        self._next = 0  # the next track sample to take
        self._last: float | None = None
        self._held: np.ndarray | None = None  # live: the last frame's inputs, and when they came
        self._held_at: float | None = None

    def moving(self) -> bool:
        """Whether something the drivers move is still swinging (a live view keeps drawing)."""
        return self.physics is not None and self.physics.moving()

    def row(self, values: np.ndarray, extra: Mapping[str, float] | None) -> np.ndarray:
        """The drivers' input row ``(len(codes),)``: the 21 motors, then the face's parameters
        (``extra``'s where given, else at rest)."""
        given = extra or {}
        return np.concatenate([np.asarray(values, dtype=float)[:N_MOTORS],
                               [given.get(c, self.rests[c]) for c in self.codes[N_MOTORS:]]])

    def extra_at(self, t: float, values: np.ndarray, extra: Mapping[str, float] | None) -> dict[str, float]:
        """The parameters to draw at ``t`` seconds for the motors ``values`` ``(21,)`` and the
        parameters ``extra`` (by code) the frame has: those, with what the drivers move added
        (kept within [0, 1]). Times go forward; a time before the last (a looping track
        starting again) starts the drivers afresh."""
        out = dict(extra or {})
        if self.physics is None:
            return out
        if self._last is not None and t < self._last - 1e-9:
            self.physics.reset()
            self._next, self._held, self._held_at = 0, None, None
        self._last = t
        if self._rows is not None and self._times is not None:
            times = self._times
            while self._next < len(times) and times[self._next] <= t + 1e-9:
                self.physics.advance(float(times[self._next]), self._rows[self._next])
                self._next += 1
            row = self._track_row(t)  # the track's own values at t (what a frame there shows, before mixing)
        else:  # live: linear from the last frame, or after a pause (a face idle in the studio) held till just before
            row = self.row(values, extra)
            if self._held is not None and self._held_at is not None and t - self._held_at > GAP:
                self.physics.advance(t - GAP, self._held)
            self.physics.advance(t, row)
            self._held, self._held_at = row, t
            if not self.physics.moving():  # all but stopped: at rest exactly (a still face is drawn as still)
                self.physics.settle()
        for param, moved in self.physics.outputs(t, row).items():
            out[param] = min(max(float(out.get(param, self.rests[param]) + moved), 0.0), 1.0)
        return out

    def _track_row(self, t: float) -> np.ndarray:
        """The track's input row at ``t``, linear between its samples (held beyond its ends), as
        ``np.interp`` gives it column by column."""
        assert self._rows is not None and self._times is not None
        times = self._times
        k = int(np.searchsorted(times, t, side="right"))
        if k <= 0:
            return self._rows[0]
        if k >= len(times):
            return self._rows[-1]
        if t == times[k - 1]:  # on a sample (a frame at the track's rate): that sample (finite: the line's share is 0)
            return self._rows[k - 1]
        share = (t - times[k - 1]) / (times[k] - times[k - 1])
        return self._rows[k - 1] + (self._rows[k] - self._rows[k - 1]) * share

    def _track_rows(self, track: MotorTrack) -> np.ndarray:
        """The track's samples as input rows ``(frames, len(codes))`` (a parameter it lacks at rest)."""
        table = track.table()
        columns = [table[:, N_MOTORS + track.extra_codes.index(c)] if c in track.extra_codes
                   else np.full(track.frames, self.rests[c]) for c in self.codes[N_MOTORS:]]
        return np.column_stack([table[:, :N_MOTORS], *columns]) if columns else table[:, :N_MOTORS]
