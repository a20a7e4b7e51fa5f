"""Cleaning and mapping one frame at a time, for a live sender: the ``step`` form of the pipeline.

Per frame, in the offline order where the future is not needed: the robust head fit (on the
performer's reference shape: the profile's, kept when it was calibrated, or else measured on the
rest as offline cleaning measures it, :meth:`LiveMapper._own_shape_at_rest`), spikes rejected in
the head frame and the head fitted again without them, lost markers filled from the markers seen
now, or held at their last head-frame position (:mod:`mapping.live_gaps`; counted as filled; a
channel such as a blendshape score held likewise), One Euro smoothing of the head-frame markers
and of the head pose, then the mapping's motor values (:func:`mapping.mapper.motor_values`) on
that one frame and the per-frame rules (:class:`mapping.rules.MotorRules`), the same code
offline mapping runs. Only cleaning differs:
offline it looks ahead (zero-phase smoothing, gap filling from both sides); live it cannot, so
live motors lag the offline ones by a frame or two and fill gaps from the past alone.

Two ways round work that would change nothing: a tracker that reports the head's rotation (a
bridge, whose frames are the head references it turned) gives the pose the fit would find, so
it is taken as it is; and where no rule reads a marker (scores and the head alone, as the
``arkit`` mapping), the markers are not cleaned.

The rest pose: with ``rest_seconds`` > 0 the first such seconds (with a head pose) are taken as
rest, as ``toonface map`` does by default; the profile's ranges are kept around that rest and
the motors show the face's neutral meanwhile. A profile with a solver (``calibrate --solve``,
:mod:`mapping.solver`) solves its motors all at once on every frame, as offline mapping does,
about the markers' rest taken at the start.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from capture import MarkerSet
from capture.sources import Frame
from mapping.clean import head_references, reference_labels
from mapping.eye_contact import LiveEyeContact
from mapping.filters import OneEuro
from mapping.learning import RangeLearner
from mapping.life import LiveLife
from mapping.live_gaps import REGRESS_SECONDS, LiveGapFiller
from mapping.mapfile import Mapping
from mapping.mapper import FILLED_QUALITY, check_profile, made_up, marker_quality, motor_values
from mapping.outliers import SpikeFilter
from mapping.plan import MotorPlan
from mapping.profile import Profile, SourceRange, merge_profile
from mapping.rules import MotorRules
from mapping.settings import HOLD_SECONDS
from mapping.solver import rests_of
from mapping.sources import head_angles, measure
from mapping.stabilise import Stabilised, measured_shape, nearest_rotation, robust_rigid_fit, to_head_frame
from toon import N_MOTORS, standard_neutral
from toon.motors import code_index, extended_neutral

#: One Euro settings (Hz, and per mm/s) for head-frame markers live: 1 frame of lag at 60 Hz
#: (``python -m bench fidelity`` measures this filter). A speed coefficient of 1 (no lag; a still
#: marker's jitter 2.21 times smaller against 2.68), with the pose filtered as :data:`POSE_LEVER_MM`
#: says, lowered the live fitted error summed over its choice takes 33.77 -> 33.51 %, but raised the
#: second and third performers' (6.48 -> 6.52, 9.16 -> 9.20): kept at 0.5.
LIVE_MIN_CUTOFF, LIVE_BETA = 1.0, 0.5
#: The head's pose is filtered by the same One Euro as the markers, its rotation as the motion it
#: gives a point this many mm from the head's origin (its matrix's entries times this), so that the
#: speed coefficient, per mm/s, means the same for a turn as for a marker. The matrix's entries
#: themselves, unitless, moved at a hundredth of a marker's speed in a turn, and the head's filter
#: stayed near its 1 Hz floor: the head motors trailed a turn by 40-80 ms (the fourth performer's
#: choice seeds 31 and 32: HH by 5 and 10 frames at 120 Hz, HV by 8 and 9; seed 31 now by 0 and 1).
#: Chosen on the four bench performers' choice seeds (fourth 31-34, the others' 31 and 32; live
#: fitted error): the 10 takes all lower, 34.48 -> 33.77 % summed (fourth 31 2.605 -> 2.542, second
#: 31 3.546 -> 3.473, third 31 4.329 -> 4.289, own 31 2.794 -> 2.695); 50, 100 and 200 mm within
#: 0.004 of each other on every take (the markers' speed coefficient at 1).
POSE_LEVER_MM = 100.0


class LiveMapper:
    """Map a stream of marker frames to motor frames.

    Parameters
    ----------
    mapping, markerset, profile
        As for :func:`mapping.map_stabilised`; the profile must hold every source's range.
    labels : sequence of str
        The incoming frames' marker names (the marker set's or its aliases).
    rate : float
        Frames per second (for filters and delays).
    target_neutral : ndarray, shape (21,), optional
    rest_seconds : float
        Seconds at the start taken as the performer's rest (0: the profile's rest as it is).
    hold_seconds : float
        A marker unseen for up to this long holds its last head-frame position, where it is not
        regressed on the markers seen (:mod:`mapping.live_gaps`), and a blendshape channel its last
        value (offline cleaning's ``max_gap_seconds`` is ``regress_seconds`` here: how long a gap
        is filled at all).
    regress_seconds : float
        A lost marker that no ``pair`` rule reads is regressed on the markers seen for up to this
        long (0: held as the others).
    spikes : bool
    seed : int
        Seeds the idle drift and the tremble.
    learn_seconds : float
        Above 0: the ranges are learned as the stream runs, for this long after the rest
        (:mod:`mapping.learning`), and ``profile`` need hold no ranges (a camera with no profile).
    channel_names : sequence of str
        Names of the incoming frames' channels (blendshape scores), if they have any.
    """

    def __init__(self, mapping: Mapping, markerset: MarkerSet, profile: Profile, labels: tuple[str, ...],
                 rate: float, target_neutral: np.ndarray | None = None, rest_seconds: float = 1.0,
                 hold_seconds: float = HOLD_SECONDS, spikes: bool = True, seed: int = 0, learn_seconds: float = 0.0,
                 channel_names: tuple[str, ...] = (), regress_seconds: float = REGRESS_SECONDS) -> None:
        if mapping.style.time_scale != 1.0:
            raise ValueError(f"mapping {mapping.name}: a live stream cannot change the time scale")
        if learn_seconds > 0 and rest_seconds <= 0:
            raise ValueError("ranges learned live need a rest to start from (rest_seconds > 0)")
        if learn_seconds <= 0:
            check_profile(mapping, profile)
        self.learn_seconds = learn_seconds
        self.learner: RangeLearner | None = None
        self._plan: MotorPlan | None = None  # motor_values' arrays, for the profile it was made for
        self._plan_for: Profile | None = None
        self.mapping, self.profile, self.rate = mapping, profile, rate
        self.columns = {label: list(labels).index(name) for label, name in markerset.match(labels).items()}
        self.rows: list[int] = []
        self.shape = np.empty((0, 3))
        self._named: list[str] = []  # the head references' labels, in the order of ``rows``
        #: Whether the head is fitted on the performer's own reference shape (the profile's, or
        #: measured on the rest: :meth:`_own_shape_at_rest`); until then, on the marker set's.
        self.own_shape = True
        if markerset.labels:  # a set with markers has a head to find; a voice has none (nothing to stabilise)
            references = head_references(labels, markerset)
            if not references:
                raise ValueError(str(references))
            self.rows, self.shape = references
            self._named = reference_labels(labels, markerset)
            self.own_shape = bool(profile.references) and all(label in profile.references for label in self._named)
            if self.own_shape:
                self.shape = np.array([profile.references[label] for label in self._named])  # as calibration fitted
        self.neutral = standard_neutral() if target_neutral is None else np.asarray(target_neutral, dtype=float)
        self.hold_seconds, self.rest_seconds = hold_seconds, rest_seconds
        self.spikes = SpikeFilter() if spikes else None
        self.markers = OneEuro(LIVE_MIN_CUTOFF, LIVE_BETA, rate=rate)
        self.pose = OneEuro(LIVE_MIN_CUTOFF, LIVE_BETA, rate=rate)
        self.rules = MotorRules(mapping, rate, self.neutral, seed)
        paired = {m for rule in mapping.rules if rule.loss == "pair" for source in rule.sources for m in source.markers}
        self.gaps = LiveGapFiller(len(labels), rate, [c for label, c in self.columns.items() if label not in paired],
                                  hold_seconds, regress_seconds,
                                  [self.columns[label] for label in markerset.independent if label in self.columns])
        self.reads_markers = any(source.markers for source in mapping.sources())
        self.channel_names = tuple(channel_names)
        read = {source.channel for source in mapping.sources() if source.kind == "blendshape"}
        self._read = [(i, name) for i, name in enumerate(self.channel_names) if name in read]  # the rest: unused
        self._last_channels = np.full(len(self.channel_names), np.nan)
        self._channel_seen = np.full(len(self.channel_names), -np.inf)
        self._rest: list[tuple[np.ndarray, np.ndarray, dict[str, np.ndarray], np.ndarray]] = []
        self._rest_start: float | None = None
        self._ready = rest_seconds <= 0
        #: The parameters beyond the 21 the mapping drives (HT...), and their values in the frame
        #: the last :meth:`step` returned (at their neutral before the rest is taken).
        self.extra_codes: tuple[str, ...] = mapping.extra_codes
        self._extra_columns = [code_index(code) for code in self.extra_codes]
        self.extra = extended_neutral(self.neutral)[self._extra_columns]
        #: Eye contact (:mod:`mapping.eye_contact`), stepped on every frame after the rest, where set.
        self.eye_contact: LiveEyeContact | None = None
        #: The life layer (:mod:`mapping.life`), laid on every frame after the rest, where set.
        self.life: LiveLife | None = None

    @property
    def ready(self) -> bool:
        """Whether the rest has been taken (and :attr:`profile` holds it)."""
        return self._ready

    def step(self, positions: np.ndarray, t: float, channels: np.ndarray | None = None, trust: float = 1.0,
             head: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
        """One frame of world marker positions ``(M, 3)`` (NaN unseen) and channels ``(C,)``
        (NaN or None: not measured) at ``t`` seconds; returns the motors ``(21,)`` in [0, 1] and
        their confidence ``(21,)`` (1 seen, 0.5 held, 0 lost), times ``trust``: how sure the
        tracker that made the frame was (0..1); the parameters beyond the 21 are then in
        :attr:`extra` (``(len(extra_codes),)``, by :attr:`extra_codes`, :meth:`extra_values`).
        ``head``: the head's rotation ``(3, 3)`` where the tracker reports it (a bridge's, whose
        head references it turned), taken as the pose instead of one fitted to the references."""
        local, rotation, translation, ok = self._head_frame(np.asarray(positions, dtype=float), t, head)
        if self.reads_markers:
            local, held = self.gaps.step(local, t)
            quality = marker_quality(local)
            quality[held] = FILLED_QUALITY
            local = self.markers.step(local.reshape(-1), t).reshape(local.shape)
        else:  # scores and the head alone: nothing reads the markers, so nothing cleans them
            quality = marker_quality(local)
        if ok:
            pose = self.pose.step(np.concatenate([rotation.reshape(-1) * POSE_LEVER_MM, translation]), t)
            rotation, translation = nearest_rotation(pose[:9].reshape(3, 3) / POSE_LEVER_MM), pose[9:]
        stable = Stabilised(local[None], rotation[None], translation[None], np.array([ok]), self.shape,
                            channels=self._hold_channels(channels, t))
        if not self._ready:
            self._collect_rest(stable, t, positions)
            return self.neutral.copy(), np.zeros(N_MOTORS)
        values, confidence = self.map_frame(stable, quality[None], t)
        confidence = confidence * min(max(trust, 0.0), 1.0)
        if self.eye_contact is not None:  # the pupils centred on the screen's look, once calibrated
            values = self.eye_contact.step(values, t)
        if self.life is not None:  # on the motors the mapping does not drive, or has lost
            values, confidence = self.life.step(values, confidence, t, self._heard("sound_level", channels),
                                                self._heard("voice_pitch", channels), self.extra, self.extra_codes)
        return values, confidence

    def _heard(self, name: str, channels: np.ndarray | None) -> float:
        """This frame's value of the channel ``name`` (a voice's level or pitch), 0 where the
        source has none or did not measure it."""
        if channels is None or name not in self.channel_names:
            return 0.0
        value = float(channels[self.channel_names.index(name)])
        return value if np.isfinite(value) else 0.0

    def extra_values(self) -> dict[str, float]:
        """The last frame's parameters beyond the 21 by code (empty when the mapping drives none)."""
        return {code: float(v) for code, v in zip(self.extra_codes, self.extra, strict=True)}

    def step_frame(self, frame: Frame) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`step` on a source's frame: its positions, channels, confidence and head."""
        return self.step(frame.positions, frame.t, frame.channels,
                         1.0 if frame.confidence is None else frame.confidence, frame.head)

    def _head_frame(self, positions: np.ndarray, t: float, head: np.ndarray | None
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, bool]:
        """Head-frame markers ``(M, 3)``, the pose and whether there is one; spikes removed
        (but from a tracker's own head where the mapping reads no markers: nothing to remove)."""
        if not self.rows:  # no markers, no head: the frame is its own head frame
            return positions.copy(), np.eye(3), np.zeros(3), True
        given = head is not None and np.isfinite(head).all() and np.isfinite(positions[self.rows]).all()
        if given:  # the tracker's turn; the references' shift where it leaves them
            rotation = np.asarray(head, dtype=float)[None]
            translation = (positions[self.rows] - self.shape @ rotation[0].T).mean(axis=0)[None]
        else:
            rotation, translation, fitted = robust_rigid_fit(self.shape, positions[None, self.rows])
            if not fitted[0]:
                return np.full(positions.shape, np.nan), np.full((3, 3), np.nan), np.full(3, np.nan), False
        local = to_head_frame(positions[None], rotation, translation)[0]
        if self.spikes is not None and (self.reads_markers or not given):
            kept = self.spikes.step(local, t)
            spiked = np.isnan(kept[:, 0]) & ~np.isnan(local[:, 0])
            if spiked[self.rows].any() and not given:  # fit again without the spiked references
                cleaned = np.where(spiked[:, None], np.nan, positions)
                rotation, translation, fitted = robust_rigid_fit(self.shape, cleaned[None, self.rows])
                if not fitted[0]:
                    return np.full(positions.shape, np.nan), np.full((3, 3), np.nan), np.full(3, np.nan), False
                kept = np.where(spiked[:, None], np.nan, to_head_frame(positions[None], rotation, translation)[0])
            local = kept
        return local, rotation[0], translation[0], True

    def _hold_channels(self, channels: np.ndarray | None, t: float) -> dict[str, np.ndarray]:
        """This frame's channels that the mapping reads, by name, ``(1,)`` each, a missing value
        held for ``hold_seconds``."""
        if not self._read:
            return {}
        values = np.full(len(self.channel_names), np.nan) if channels is None else np.asarray(channels, dtype=float)
        seen = np.isfinite(values)
        self._last_channels[seen], self._channel_seen[seen] = values[seen], t
        held = np.where(~seen & (t - self._channel_seen <= self.hold_seconds), self._last_channels, values)
        return {name: held[i:i + 1] for i, name in self._read}

    def _collect_rest(self, stable: Stabilised, t: float, positions: np.ndarray) -> None:
        if not stable.ok[0]:
            return
        self._rest_start = t if self._rest_start is None else self._rest_start
        self._rest.append((stable.local[0], stable.rotation[0], stable.channels, np.asarray(positions, dtype=float)))
        if t - self._rest_start + 1.0 / self.rate >= self.rest_seconds:
            self.profile = self._profile_at_rest()
            self._ready = True

    def _profile_at_rest(self) -> Profile:
        """The profile with its ranges kept around the rest measured at the start."""
        local = np.array([f[0] for f in self._rest])
        rotations = np.array([f[1] for f in self._rest])
        if not self.own_shape:  # the head fitted on the performer's references from here on, the rest too
            local, rotations = self._own_shape_at_rest(np.array([f[3] for f in self._rest]), local, rotations)
        channels = {name: np.concatenate([f[2][name] for f in self._rest]) for _, name in self._read}
        rest_rotation = nearest_rotation(rotations.mean(axis=0))
        head = head_angles(rotations, rest_rotation, self.profile.head_axes)
        rests = {}
        for source in self.mapping.sources():
            measured = measure(source, local, self.columns, head, channels)
            if np.isfinite(measured).any():
                rest = float(np.nanmedian(measured))
                rests[source.key] = SourceRange(rest, rest, rest)
        references = dict(zip(self._named, self.shape, strict=True))  # kept, should the profile be saved
        own = Profile(self.profile.markerset, rests, rest_rotation, head_axes=self.profile.head_axes,
                      references=references)
        if self.learn_seconds > 0:
            learner = self.learner = RangeLearner(own, freeze_after=self.learn_seconds)
            return learner.profile
        merged = merge_profile(self.profile, own, [], rest_from_take=True, rest=rests_of(local, self.columns))
        return replace(merged, references=references)

    def _own_shape_at_rest(self, world: np.ndarray, local: np.ndarray, rotations: np.ndarray
                           ) -> tuple[np.ndarray, np.ndarray]:
        """The performer's head references measured on the rest's world markers ``world`` ``(F, M, 3)``
        (:func:`mapping.stabilise.measured_shape`, as offline cleaning measures them) and fitted
        on from now on; the rest's head-frame markers ``(F, M, 3)`` and head rotations ``(F, 3, 3)``
        with it (``local``, ``rotations``: as the marker set's shape gave them, kept where the
        fit fails). The filters start again in the new head frame."""
        self.shape, self.own_shape = measured_shape(world[:, self.rows], self.shape), True
        rotation, translation, ok = robust_rigid_fit(self.shape, world[:, self.rows])
        local, rotations = local.copy(), rotations.copy()
        local[ok], rotations[ok] = to_head_frame(world[ok], rotation[ok], translation[ok]), rotation[ok]
        for reset in (self.markers, self.pose, self.spikes, self.gaps):
            if reset is not None:
                reset.reset()
        return local, rotations

    def map_frame(self, stable: Stabilised, quality: np.ndarray, t: float) -> tuple[np.ndarray, np.ndarray]:
        """The mapping of one cleaned frame (``stable`` holds one frame; ``quality`` ``(1, M)``):
        motors ``(21,)`` and confidence ``(21,)``; what offline mapping gives that frame."""
        learner = self.learner if self.learner is not None and not self.learner.frozen else None
        learning = learner is not None
        if learner is not None:
            head = head_angles(stable.rotation, self.profile.rest_rotation, self.profile.head_axes)
            learner.update({source.key: float(measure(source, stable.local, self.columns, head,
                                                           stable.channels)[0])
                                 for source in self.mapping.sources()}, t)
        if self._plan is None:
            self._plan = MotorPlan.of(self.mapping.rules, self.profile, self.columns)
        elif learning or self._plan_for is not self.profile:
            # kept while the profile stands; a learner widens its ranges in place, frame by frame
            self._plan = self._plan.under(self.mapping.rules, self.profile)
        self._plan_for = self.profile
        raw, confidence = motor_values(self.mapping, stable, self.columns, quality, self.profile, self.neutral,
                                       self._plan)
        stepped = self.rules.step(raw[0], t, made_up(confidence[0]))
        self.extra = stepped[self._extra_columns]  # the parameters beyond the 21, beside the motors returned
        return stepped[:N_MOTORS], np.clip(confidence[0, :N_MOTORS], 0.0, 1.0)
