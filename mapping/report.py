"""What was chosen for a mapped take, and how far to trust it: the report ``map``, ``retarget``
and each batch pair end with.

It names the units (and who said them, with the size check's figure), the rest window and why,
the profile (given, calibrated, typical, from the take), per mapped motor the share of frames
pinned at 0 and at 1 and the share of its range used, and every warning. A motor pinned at a
bound it does not rest at for more than :data:`PINNED_SHARE` of the take is a warning: its range
is narrower than the take's motion (or the rest is wrong), and the cartoon holds still there.
A motor that no seen marker drove for :data:`GUESSED_SECONDS` or more at a stretch (its markers
hidden, filled from the others or left to the loss policy) is named in a note with its longest
stretch: there it moves as the other markers foretell, and a motion of its own is lost (a head
turned away hid one brow's outer marker while that brow alone was raised: the fourth bench
performer's outer brow read 0.63 where it was at 0.88).
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from mapping.gaps import gap_runs
from mapping.mapper import made_up
from toon import MOTOR_CODES, MotorTrack

if TYPE_CHECKING:
    from mapping.ready import ReadyTake

#: A motor value within this of 0 or 1 is pinned there.
PINNED_WITHIN = 0.005
#: Pinned at a bound it does not rest at for more than this share of the frames: a warning.
PINNED_SHARE = 0.10
#: A motor rests at a bound when its neutral is within this of it.
RESTS_AT = 0.05
#: A motor driven by no seen marker for this long (s) at a stretch is named in a note.
GUESSED_SECONDS = 1.0
WARNING = "warning: "


@dataclass(frozen=True)
class TakeReport:
    """The report of one mapped take (see the module docstring).

    Attributes
    ----------
    take : str
        The take's file name.
    units, rest, profile : str
        What was chosen, in words.
    motors : dict of str to dict
        Per mapped motor: ``at_0`` and ``at_1`` (shares of frames pinned there) and
        ``range_used`` (1st to 99th percentile spread, a share of the motor's range).
    warnings, notes : list of str
        Without their ``warning:``/``note:`` prefixes.
    units_detail : dict
        The units as data (:meth:`mapping.units.Units.as_dict`).
    """

    take: str
    units: str
    rest: str
    profile: str
    motors: dict[str, dict[str, float]]
    warnings: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    units_detail: dict[str, Any] = field(default_factory=dict)

    def as_dict(self) -> dict[str, Any]:
        """The report as data (``--json``, the batch manifest)."""
        return {"take": self.take, "units": self.units_detail or self.units, "rest": self.rest,
                "profile": self.profile, "motors": self.motors, "warnings": self.warnings, "notes": self.notes}

    @classmethod
    def from_dict(cls, doc: dict[str, Any]) -> TakeReport:
        """The report :meth:`as_dict` gave (a track's ``meta["report"]``)."""
        units = doc.get("units", "")
        text = (f"{units['unit']} ({units['from']}; {units['check']})" if isinstance(units, dict) else str(units))
        return cls(str(doc.get("take", "")), text, str(doc.get("rest", "")), str(doc.get("profile", "")),
                   dict(doc.get("motors", {})), list(doc.get("warnings", [])), list(doc.get("notes", [])),
                   units if isinstance(units, dict) else {})

    def lines(self) -> list[str]:
        """The report as text, one item a line (the motors four to a line)."""
        out = [f"report for {self.take}:", f"  units: {self.units}", f"  rest: {self.rest}",
               f"  profile: {self.profile}",
               "  motors (frames at 0 / at 1, range used):"]
        cells = [f"{code} {m['at_0']:4.0%}/{m['at_1']:4.0%} {m['range_used']:4.0%}" for code, m in self.motors.items()]
        out += ["    " + "   ".join(cells[i:i + 4]) for i in range(0, len(cells), 4)]
        out += [f"  {WARNING}{w}" for w in self.warnings] + [f"  note: {n}" for n in self.notes]
        return out


def take_report(ready: ReadyTake, track: MotorTrack, neutral: np.ndarray, take: str = "") -> TakeReport:
    """The report of ``track``, mapped from ``ready`` onto a face whose rest is ``neutral`` ``(21,)``."""
    units = ready.prepared.units
    detail = units.as_dict() if units is not None else {}
    units_text = f"{detail['unit']} ({detail['from']}; {detail['check']})" if detail else "not checked"
    if not ready.prepared.take.markers:  # a voice: scores, no lengths
        units_text, detail = "none (no markers: the take's channels are scores)", {}
    warned = [n[len(WARNING):] for n in ready.notes if n.startswith(WARNING)]
    notes = [n for n in ready.notes if not n.startswith(WARNING)]
    finished = track.meta.get("blinks_finished_s", [])
    if finished:  # mapping.blink_gaps
        blinks, them = ("a blink", "it") if len(finished) == 1 else (f"{len(finished)} blinks", "them")
        notes.append(f"both upper lids' markers were lost together in {blinks}, at "
                     f"{', '.join(f'{t:g}' for t in finished)} s: the lids finish {them} as the take's own blinks "
                     "reopen, not as the gaps were filled")
    mapped = [c for c in MOTOR_CODES if c in track.meta.get("mapped", MOTOR_CODES)]
    columns = [MOTOR_CODES.index(c) for c in mapped]
    if track.confidence is not None and ready.prepared.take.markers:
        times = ready.prepared.take.times  # the track's frames: the take's, stretched by style's time_scale
        stretches = guessed_stretches(track.confidence[:, columns], track.rate * ready.mapping.style.time_scale,
                                      mapped, float(times[0]) if len(times) else 0.0)
        if stretches:
            notes.append(f"no seen marker drove these for {GUESSED_SECONDS:g} s or more at a stretch (their markers "
                         "hidden: filled from the others, or the loss policy): there they move as the other markers "
                         "foretell, and a motion of their own (one brow raised alone) is lost; the longest stretch "
                         "and the share of the take in all: " + ", ".join(stretches))
    motors: dict[str, dict[str, float]] = {}
    values = track.values[:, columns]
    seen = np.isfinite(values)
    count = np.maximum(seen.sum(axis=0), 1)
    lows = (seen & (values <= PINNED_WITHIN)).sum(axis=0) / count
    highs = (seen & (values >= 1 - PINNED_WITHIN)).sum(axis=0) / count
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # a motor never seen
        spreads = np.ptp(np.nanpercentile(np.clip(values, 0.0, 1.0), [1.0, 99.0], axis=0), axis=0)
    for i, code in enumerate(mapped):
        if not seen[:, i].any():
            continue
        low, high = float(lows[i]), float(highs[i])
        motors[code] = {"at_0": round(low, 4), "at_1": round(high, 4), "range_used": round(float(spreads[i]), 4)}
        rest = float(neutral[MOTOR_CODES.index(code)])
        for share, bound, word in ((low, 0.0, "bottom"), (high, 1.0, "top")):
            if share > PINNED_SHARE and abs(rest - bound) > RESTS_AT:
                warned.append(f"{code} is pinned at {bound:g} (its {word}) in {share:.0%} of the frames, and rests "
                                f"at {rest:.2f}: the take moves beyond the profile's range there (or the rest is "
                                "not a rest); a calibration (--calibrate) or --neutral may fit it")
    return TakeReport(take or ready.prepared.take.meta.get("file", "the take"), units_text, ready.rest or "given",
                      ready.profile_kind or "given", motors, warned, notes, detail)


def guessed_stretches(confidence: np.ndarray, rate: float, codes: list[str], start: float = 0.0) -> list[str]:
    """Each motor (``codes``, the columns of ``confidence`` ``(F, K)``) that no seen marker drove
    (:func:`mapping.mapper.made_up`, or lost: confidence 0) for at least
    :data:`GUESSED_SECONDS` at a stretch, as "code, its longest stretch (s) and when it began (s,
    the first frame at ``start``), its share of the frames in all"; frames at ``rate`` per second of
    the take (a track's rate times the time scale that stretched it).

    >>> conf = np.ones((300, 2))
    >>> conf[30:150, 0], conf[200:210, 0], conf[10:40, 1] = 0.5, 0.0, 0.5
    >>> guessed_stretches(conf, 100.0, ["BLL", "BLC"], start=2.0)
    ['BLL 1.2 s at 2.3 s (43%)']
    """
    confidence = np.asarray(confidence)
    unseen = made_up(confidence) | (confidence <= 0.0)
    out = []
    for k, code in enumerate(codes):
        runs = gap_runs(unseen[:, k])
        if not runs:
            continue
        first, end = max(runs, key=lambda run: run[1] - run[0])
        seconds = (end - first) / rate
        if seconds >= GUESSED_SECONDS:
            out.append(f"{code} {seconds:.1f} s at {start + first / rate:.1f} s ({unseen[:, k].mean():.0%})")
    return out
