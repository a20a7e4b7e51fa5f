"""Clean a take offline: spikes out, head motion removed, gaps filled, trajectories smoothed.

The order matters. Head motion goes first, so that the spike test sees the face's own slow
motion (a fast head turn would otherwise look like a spike): a robust rigid fit of the head
references expresses every marker in the head frame (the references' own spikes are found
before it, in the world, by :func:`~mapping.outliers.centred_spikes`: with few references seen,
one spike turns the whole head). Two neighbouring markers that traded labels for a few frames
get them back there (:mod:`mapping.swaps`). Spikes are then rejected there, by the live test and by the
offline one that looks both ways (on the head references too), and the head is fitted again
without them, with the performer's reference shape the first fit measured. A frame with too few
references seen, or only ones on a line, has no pose; a short stretch of them takes one carried
across from the poses either side (:func:`~mapping.lost_poses.bridge_lost_poses`), set right by
the references still seen there as far as they pin it (:func:`~mapping.lost_poses.refine_poses`:
the midline's three pitch it where the head nods), and by the face's other markers as far as they
hold still in the head (:func:`~mapping.lost_poses.weak_references`). Gaps are filled
in the head frame (from both sides, and from the other markers for long ones; a marker set's
independent markers, the pupils, only from each other or straight across), then everything is
smoothed with a zero-phase low-pass, which has no lag because it may look ahead, and more
heavily where a marker holds still (:mod:`mapping.holds`: a held lid or gaze without its
jitter, a blink as sharp as before, a new pose less rounded). The head pose is smoothed with
the low-pass alone. Samples left unseen (gaps too long to fill) stay NaN. A take's channels (a
markerless tracker's blendshape scores) are filled across the same short gaps, straight from
one side to the other, and smoothed by the same low-pass.

A take whose markers match no known marker set (or lack the head references) is cleaned as it
is, in world coordinates, and the report says so.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from capture import MarkerSet, Take
from capture.markerset import find_markerset
from common import Failure
from common.rotations import rigid_fit
from mapping.filters import Butterworth
from mapping.gap_fit import straight_line
from mapping.gaps import GapFiller, gap_runs
from mapping.holds import HoldSmoother, fast_moves, marker_noise, put_back_moves
from mapping.lost_poses import bridge_lost_poses, refine_poses, weak_references
from mapping.outliers import SpikeFilter, centred_spikes
from mapping.reference_bridge import bridge_edge, fade_frames
from mapping.robust import jitter
from mapping.settings import CleanSettings
from mapping.stabilise import (
    Stabilised,
    express,
    fit_head,
    nearest_rotation,
    posedness,
    refit_head,
    to_head_frame,
    yaw_pitch_degrees,
)
from mapping.swaps import find_swaps, undo_swaps


@dataclass(frozen=True, eq=False)
class CleanReport:
    """What cleaning did: counts of marker-samples ``rejected``, ``filled`` and ``still_missing``,
    frames without a head pose (``no_head_frames``), frames whose pose was carried across from either side
    (``bridged``, :func:`mapping.lost_poses.bridge_lost_poses`), how head motion was handled (``head``) and how
    many label swaps of two neighbouring markers were undone (``swaps``, :mod:`mapping.swaps`)."""

    rejected: int
    filled: int
    still_missing: int
    no_head_frames: int = 0
    head: str = "removed"
    bridged: int = 0
    swaps: int = 0

    def summary(self) -> str:
        """One line for the CLI."""
        return (f"{self.rejected} spikes rejected, {self.filled} samples filled, {self.still_missing} still missing, "
                f"head motion {self.head}" + (f" ({self.no_head_frames} frames without a head pose)"
                                              if self.no_head_frames else "")
                + (f"; the head pose carried across {self.bridged} frames with too few head references seen"
                   if self.bridged else "")
                + (f"; {self.swaps} label swap{'s' if self.swaps != 1 else ''} of neighbouring markers undone"
                   if self.swaps else ""))


def head_references(labels: tuple[str, ...], markerset: MarkerSet) -> tuple[list[int], np.ndarray] | Failure:
    """Columns of ``labels`` (a take's or a stream's markers) holding ``markerset``'s head
    references and their rest positions ``(K, 3)`` in the head frame, or why they cannot be used
    (fewer than three)."""
    found = markerset.match(labels)
    present = reference_labels(labels, markerset)
    if len(present) < 3:
        missing = [r for r in markerset.head_reference if r not in found]
        return Failure(f"fewer than 3 of marker set {markerset.name}'s head reference markers are present "
                       f"(missing: {', '.join(missing)})")
    return [list(labels).index(found[r]) for r in present], np.array([markerset.neutral_of(r) for r in present])


def reference_labels(labels: tuple[str, ...], markerset: MarkerSet) -> list[str]:
    """``markerset``'s head references that ``labels`` (a take's or a stream's markers) hold, by
    the marker set's names, in the order of :func:`head_references`' columns and shape."""
    found = markerset.match(labels)
    return [r for r in markerset.head_reference if r in found]


def clean_stabilised(take: Take, markerset: MarkerSet, settings: CleanSettings = CleanSettings()
                     ) -> tuple[Stabilised, CleanReport] | Failure:
    """Clean ``take`` and return it in the head frame with its (smoothed) head pose.

    Returns a :class:`~common.Failure` saying why when the head cannot be found.
    """
    if not markerset.head_reference:  # a sparse layout: no head frame to find (see fixed_frame)
        return _without_head(take, markerset, settings)
    references = head_references(take.labels, markerset)
    if not references:
        return references
    rows, neutral = references
    positions, world_spikes = take.positions, np.zeros(take.positions.shape[:2], bool)
    if settings.spikes:  # the head references' own spikes first: with few seen, one turns the whole head
        world_spikes[:, rows] = centred_spikes(take.positions[:, rows], take.times)
        positions = np.where(world_spikes[..., None], np.nan, positions)
    fit = fit_head(positions, rows, neutral)
    if isinstance(fit, Failure):
        return fit
    edge, fade = bridge_edge(take.rate), fade_frames(take.rate)
    first, bridged = _bridge_lost_poses(express(positions, rows, fit, edge, fade), positions, take.times, rows,
                                        settings.max_gap_seconds)
    rejected, swaps = 0, []
    if settings.spikes:
        del positions  # made again without the spikes: a long take's copy is hundreds of MB
        swaps = find_swaps(first.local, take.times)  # before the spike tests, which would blank a swap's first frame
        undo_swaps(first.local, swaps)
        spikes = SpikeFilter().spikes(first.local, take.times)
        local = first.local  # no longer needed once the spikes are found: they are blanked in it, not in a copy
        local[spikes] = np.nan
        spikes |= centred_spikes(local, take.times)
        del local
        new_references = np.asarray(spikes[:, rows].any(axis=1))  # frames whose fit loses a reference, or gets one back
        for swap in swaps:
            if swap.first in rows or swap.second in rows:
                new_references[swap.start:swap.end] = True
        undo_swaps(world_spikes, swaps)  # every mask and copy from here on has the labels given back
        spikes |= world_spikes
        rejected = int(spikes.sum())
        positions = take.positions.copy()
        undo_swaps(positions, swaps)
        positions[spikes] = np.nan
        fit = refit_head(fit, positions, rows, new_references)
        if isinstance(fit, Failure):
            return fit
        first, bridged = _bridge_lost_poses(express(positions, rows, fit, edge, fade), positions, take.times, rows,
                                            settings.max_gap_seconds)
    del positions  # the world positions are done with
    found = markerset.match(take.labels)
    apart = [take.index(found[m]) for m in markerset.independent if m in found]
    local, filled_mask = _fill_and_smooth(first.local, take, settings, apart)
    rotation, translation = first.rotation, first.translation
    if settings.cutoff_hz > 0 and take.frames > 1:
        rotation, translation = _smooth_pose(rotation, translation, _smoother(settings, take.rate))
    cleaned = Stabilised(local, rotation, translation, first.ok, first.reference, filled_mask,
                         clean_channels(take, settings))
    missing = int(np.isnan(local[..., 0]).sum())
    return cleaned, CleanReport(rejected, int(filled_mask.sum()), missing, int((~first.ok).sum()), bridged=bridged,
                                swaps=len(swaps))


def _bridge_lost_poses(first: Stabilised, positions: np.ndarray, times: np.ndarray, rows: list[int],
                       longest: float) -> tuple[Stabilised, int]:
    """``first`` with short stretches without a head pose given one (:func:`mapping.lost_poses.bridge_lost_poses`,
    each pose either side trusted as well as its references pin it; then :func:`mapping.lost_poses.refine_poses` by
    the references seen there, and the other markers as weak ones, :func:`mapping.lost_poses.weak_references`) and
    the markers seen there expressed in it; and how many frames were bridged. A stretch is
    bridged up to ``longest`` seconds (the longest gap filled)."""
    if first.ok.all():  # every frame has its own pose: nothing to carry across
        return first, 0
    trust = posedness(first.reference, np.isfinite(positions[:, rows, 0]))
    rotation, translation, bridged = bridge_lost_poses(first.rotation, first.translation, first.ok, times,
                                                       longest=longest, trust=trust)
    if not bridged.any():
        return first, 0
    others = [m for m in range(positions.shape[1]) if m not in rows]
    noise = jitter(positions[:, rows])
    weak = weak_references(first.local[:, others], positions[:, others], first.ok, bridged, times,
                           float(np.nanmedian(noise)) if np.isfinite(noise).any() else 0.0)
    rotation, translation = refine_poses(rotation, translation, first.reference, positions[:, rows], bridged,
                                         weak=weak)
    local = first.local.copy()
    local[bridged] = to_head_frame(positions[bridged], rotation[bridged], translation[bridged])
    return Stabilised(local, rotation, translation, first.ok | bridged, first.reference), int(bridged.sum())


def fixed_frame(take: Take, markerset: MarkerSet) -> tuple[np.ndarray, np.ndarray] | Failure:
    """For a marker set without head references (three markers on a jaw and mouth corners): the
    one rigid placement of the take in the set's head frame, ``(rotation (3, 3), translation
    (3,))`` head frame to world, fitted on the take's first second over every marker both have.
    The head's own motion is not removed: it reaches the motors as if the face moved."""
    from capture.plot import neutral_pose

    if not markerset.labels:  # a source with no markers (a voice): nothing to place
        return np.eye(3), np.zeros(3)
    found = markerset.match(take.labels)
    rest = neutral_pose(take)
    pairs = [(take.index(mine), markerset.neutral_of(label)) for label, mine in found.items()
             if np.isfinite(rest[take.index(mine)]).all()]
    if len(pairs) < 3:
        return Failure(f"only {len(pairs)} of marker set {markerset.name}'s markers are seen: cannot place the take")
    rotation, translation, _ = rigid_fit(np.array([n for _, n in pairs]), rest[[m for m, _ in pairs]][None])
    return rotation[0], translation[0]


def _without_head(take: Take, markerset: MarkerSet, settings: CleanSettings
                  ) -> tuple[Stabilised, CleanReport] | Failure:
    """:func:`clean_stabilised` for a set without head references: spikes, gaps and smoothing as
    for any take, in one fixed placement (:func:`fixed_frame`)."""
    placed = fixed_frame(take, markerset)
    if isinstance(placed, Failure):
        return placed
    rotation = np.broadcast_to(placed[0], (take.frames, 3, 3)).copy()
    translation = np.broadcast_to(placed[1], (take.frames, 3)).copy()
    local = to_head_frame(take.positions, rotation, translation)
    rejected, swaps = 0, []
    if settings.spikes:
        swaps = find_swaps(local, take.times)
        undo_swaps(local, swaps)
        spikes = SpikeFilter().spikes(local, take.times)
        rejected = int(spikes.sum())
        local = np.where(spikes[..., None], np.nan, local)
    local, filled = _fill_and_smooth(local, take, settings)
    cleaned = Stabilised(local, rotation, translation, np.ones(take.frames, bool), np.empty((0, 3)), filled,
                         clean_channels(take, settings))
    return cleaned, CleanReport(rejected, int(filled.sum()), int(np.isnan(local[..., 0]).sum()), 0,
                                head="not removed (the marker set has no head references)", swaps=len(swaps))


def clean_take(take: Take, settings: CleanSettings = CleanSettings(), markerset: MarkerSet | None = None,
               head_frame: bool = False) -> tuple[Take, CleanReport]:
    """The cleaned take (same labels, rate and times) and a report of what changed.

    Parameters
    ----------
    markerset : MarkerSet, optional
        The take's layout; found from its labels when not given.
    head_frame : bool
        Return positions in the head frame (head motion removed) instead of the world's; the head's
        yaw and pitch (degrees, per frame) go into ``meta["head"]``.
    """
    markerset = markerset or find_markerset(take.labels)
    result = clean_stabilised(take, markerset, settings) if markerset else Failure("no known marker set")
    channels = result[0].channels if result else clean_channels(take, settings)
    meta = {**take.meta, "cleaned": {"spikes": settings.spikes, "max_gap_seconds": settings.max_gap_seconds,
                                     "cutoff_hz": settings.cutoff_hz}}
    if not result:
        pos, report = _clean_world(take, settings, f"left in ({result})")
    else:
        stable, report = result
        if head_frame and markerset is not None:  # a marker set found the head
            pos = stable.local
            yaw, pitch = yaw_pitch_degrees(np.where(stable.ok[:, None, None], stable.rotation, np.eye(3)))
            meta["head"] = {"frame": markerset.name, "yaw_deg": np.where(stable.ok, yaw, np.nan).round(4).tolist(),
                            "pitch_deg": np.where(stable.ok, pitch, np.nan).round(4).tolist()}
        else:
            pos = np.where(stable.ok[:, None, None], stable.world(), take.positions)
            report = replace(report, still_missing=int(np.isnan(pos[..., 0]).sum()),
                             head="removed while cleaning, then restored")
    meta["cleaned"].update(rejected=report.rejected, filled=report.filled, head=report.head, swaps=report.swaps)
    cleaned = Take(pos, take.labels, take.rate, times=take.times, dims=take.dims, meta=meta,
                   channels=np.column_stack([channels[n] for n in take.channel_names]) if channels else take.channels,
                   channel_names=take.channel_names)
    return cleaned, report


def clean_channels(take: Take, settings: CleanSettings) -> dict[str, np.ndarray]:
    """The take's channels by name, ``(F,)`` each: gaps up to ``settings.max_gap_seconds`` with
    values on both sides filled by a straight line, then smoothed as markers are."""
    values = np.array(take.channels, dtype=np.float64)
    longest = settings.max_gap_frames(take.rate)  # frames, as markers' gaps are counted
    if longest > 0 and take.frames > 1:
        for c in range(values.shape[1]):
            column = values[:, c]
            for start, end in gap_runs(np.isnan(column)):
                if start > 0 and end < take.frames and end - start <= longest:
                    column[start:end] = straight_line(column, take.times, start, end)
    if settings.cutoff_hz > 0 and take.frames > 1 and values.size:
        values = _smoother(settings, take.rate).smooth_offline(values)
    return {name: values[:, c] for c, name in enumerate(take.channel_names)}


def _clean_world(take: Take, settings: CleanSettings, head: str) -> tuple[np.ndarray, CleanReport]:
    """Clean in world coordinates (no head fit)."""
    pos, rejected = take.positions, 0
    if settings.spikes:
        pos = SpikeFilter().apply(pos, take.times)
        rejected = int((np.isnan(pos[..., 0]) & ~np.isnan(take.positions[..., 0])).sum())
    pos, filled = _fill_and_smooth(pos, take, settings)
    return pos, CleanReport(rejected, int(filled.sum()), int(np.isnan(pos[..., 0]).sum()), 0, head)


def _smoother(settings: CleanSettings, rate: float) -> Butterworth:
    return Butterworth(min(settings.cutoff_hz, 0.45 * rate), rate)


def _fill_and_smooth(positions: np.ndarray, take: Take, settings: CleanSettings, apart: list[int] | None = None
                     ) -> tuple[np.ndarray, np.ndarray]:
    """Gap filling (``apart``: columns filled only from each other, see :mod:`mapping.gaps`) then zero-phase smoothing
    of ``(F, M, 3)``, heavier where a marker holds (:mod:`mapping.holds`); returns them and which samples were filled
    ``(F, M)``."""
    pos, filled = positions, np.zeros(positions.shape[:2], dtype=bool)
    if settings.max_gap_seconds > 0 and take.frames > 1:
        result = GapFiller(max_gap_seconds=settings.max_gap_seconds).apply(pos, take.times, apart or (),
                                                                           settings.progress)
        pos, filled = result.positions, result.filled
        del result  # a long take's arrays are hundreds of MB: none kept past its use
    if settings.cutoff_hz > 0 and take.frames > 1:
        smoother = _smoother(settings, take.rate)
        noise = marker_noise(positions) if settings.holds else None  # measured once, for both
        moves = fast_moves(pos, positions, take.rate, smoother.cutoff, noise=noise) if settings.holds else []
        pos = smoother.smooth_offline(pos.reshape(take.frames, -1), overwrite=pos is not positions).reshape(pos.shape)
        if settings.holds:
            pos = put_back_moves(HoldSmoother(take.rate, smoother.cutoff).smooth(pos, positions, overwrite=True,
                                                                                 noise=noise), moves)
    return pos, filled


def _smooth_pose(rotation: np.ndarray, translation: np.ndarray, smoother: Butterworth
                 ) -> tuple[np.ndarray, np.ndarray]:
    """Zero-phase smoothing of a pose track; rotations are smoothed element-wise, then made
    rotations again (nearest by SVD). Frames without a pose stay NaN."""
    frames = len(rotation)
    smooth_rot = smoother.smooth_offline(rotation.reshape(frames, 9)).reshape(frames, 3, 3)
    ok = np.isfinite(smooth_rot).all(axis=(1, 2))
    fixed = nearest_rotation(np.where(ok[:, None, None], smooth_rot, np.eye(3)))
    fixed[~ok] = np.nan
    return fixed, smoother.smooth_offline(translation)
