"""``python -m bench.life_fit``: choose the life layer's fitted constants on the shared clips.

The constants of :class:`toon.life.LifeSettings` marked "fitted" are chosen here, each group on
the statistics it moves (:mod:`bench.life`): the gaze's fixation length on ``fixation_seconds``;
the brows' height and rise on ``brow_range`` and ``brow_speed``; the nods and the head's slow rise
and fall on ``head_range`` and ``head_speed``. The clips are split by speaker before anything is
looked at: every third speaker in name order is kept aside (:func:`held_out`). On the others, each
grid point's layer is laid on every clip and the point whose median statistics are nearest the
clips' own (the sum of squared log ratios) wins; then the winner is laid on the speakers kept
aside and its figures printed beside theirs. One JSON line per group; the constants in
``toon/life.py`` are what it printed last (11 speakers to fit, 6 aside)::

    {"group": "gaze", "chosen": {"fixation_seconds": 0.3}, "held_out": {...}}
"""

from __future__ import annotations

import itertools
import json
from dataclasses import replace
from typing import Any

import numpy as np

from bench.life import Tracked, laid, tracked
from bench.lipsync_data import clips, speaker
from common import InputError
from toon.life import LifeSettings

#: Per group: the statistics it is fitted on, and its grid (constant name -> candidates).
GROUPS: dict[str, tuple[tuple[str, ...], dict[str, tuple[float, ...]]]] = {
    "gaze": (("fixation_seconds",), {"fixation_seconds": (0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.1)}),
    "brows": (("brow_range", "brow_speed"), {"brow_raise": (0.15, 0.2, 0.3), "brow_rise_seconds": (0.15, 0.25, 0.35)}),
    "head": (("head_range", "head_speed"), {"nod": (0.02, 0.04, 0.06), "pitch_sway": (0.04, 0.06, 0.08, 0.1)}),
}


def held_out(speakers: list[str]) -> set[str]:
    """The speakers kept aside: every third in name order, from the first."""
    return set(sorted(speakers)[::3])


def fit(seen: list[Tracked]) -> list[dict]:
    """Each group's chosen constants, and their figures on the speakers fitted on and kept aside."""
    aside = held_out([clip.speaker for clip in seen])
    train = [clip for clip in seen if clip.speaker not in aside]
    test = [clip for clip in seen if clip.speaker in aside]
    out = []
    for group, (stats, grid) in GROUPS.items():
        best: tuple[float, dict[str, float]] | None = None
        for values in itertools.product(*grid.values()):
            chosen = dict(zip(grid, values, strict=True))
            loss = sum(np.log(_median(train, stat, chosen) / _median(train, stat, None)) ** 2 for stat in stats)
            if best is None or loss < best[0]:
                best = (float(loss), chosen)
        assert best is not None
        chosen = best[1]
        out.append({"group": group, "chosen": chosen, "fit_loss": round(best[0], 4),
                    "fitted_on": sorted({clip.speaker for clip in train}),
                    "fitted": {stat: _figures(train, stat, chosen) for stat in stats},
                    "held_out": {stat: _figures(test, stat, chosen) for stat in stats}})
    return out


def _figures(group: list[Tracked], stat: str, chosen: dict[str, float]) -> dict:
    """The layer's median of a statistic beside the clips' median and range."""
    real = _values(group, stat, None)
    return {"layer": round(_median(group, stat, chosen), 4), "real": round(float(np.median(real)), 4),
            "real_range": [round(min(real), 4), round(max(real), 4)]}


def _values(group: list[Tracked], stat: str, chosen: dict[str, float] | None) -> list[float]:
    """A statistic of each clip: the tracked face's (``chosen`` None), or the layer's with
    ``chosen`` over the defaults (seeded by the clip's place in its group)."""
    if chosen is None:
        found = [clip.real[stat] for clip in group]
    else:
        settings: dict[str, Any] = dict(chosen)
        found = [laid(clip, replace(LifeSettings(), seed=k, **settings))[0][stat] for k, clip in enumerate(group)]
    return [x for x in found if np.isfinite(x)]


def _median(group: list[Tracked], stat: str, chosen: dict[str, float] | None) -> float:
    return float(np.median(_values(group, stat, chosen)))


def main() -> int:
    """Track every shared clip, fit, and print one JSON line per group."""
    seen = []
    for clip in clips():
        try:
            seen.append(tracked(clip))
        except InputError as exc:
            print(json.dumps({"left_out": clip.name, "why": str(exc), "speaker": speaker(clip)}))
    if not seen:
        print(json.dumps({"skipped": "the shared talking-face clips are absent (../shared/realdata/video)"}))
        return 0
    for line in fit(seen):
        print(json.dumps(line))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
