"""A marker rig from another lab, made from a performer's take: the traps of issue 39 at once.

A real optical facial take from elsewhere broke the "your own marker layout" route: 17
unlabelled markers, metres, 120 Hz, recorded in the camera system's frame (z up, turned and
tilted away from the face), a layout about as deep as it is tall. :func:`foreign_take` makes
such a take from any performer's clean take of ``toon32`` markers, so that the truth is known:

- **Layout.** 17 of the performer's markers, moved as a lab would place them: the temple
  markers back to the tragus (120 mm behind the eyes, 12 mm lower: the layout is now about as
  deep as it is tall), the cheeks out to the jaw's angle, the forehead marker 10 mm higher,
  the chin 6 mm lower. A marker moved rides with the head (its offset is turned by the head's
  pose, found per frame from the skull markers), so its motion is the performer's.
- **Frame.** The camera system's: z up, the head frame turned 140° about it and tilted 12°,
  the face 1.4 m from the origin.
- **Table.** Columns in a seeded order, named ``Unlabeled 1001`` and on, at the performer's
  rate (120 Hz asked for), with 0.3 mm of jitter; :meth:`ForeignTake.write_csv` writes it in
  metres without a time column, as the lab's CSV was.

``truth`` keeps what the draft must find: each column's toon32 name and the head frame's axes
in the take's coordinates.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from capture import Take, load_markerset
from common.rotations import rigid_fit

#: The markers kept and how each is moved in the head frame (mm): a lab's layout, not toon32's.
LAYOUT: dict[str, tuple[float, float, float]] = {
    "FOREHEAD": (0.0, 10.0, 0.0), "TEMPLE_R": (-6.0, -12.0, -92.0), "TEMPLE_L": (6.0, -12.0, -92.0),
    "NOSE_BRIDGE": (0.0, 0.0, 0.0), "BROW_R_CEN": (0.0, 0.0, 0.0), "BROW_L_CEN": (0.0, 0.0, 0.0),
    "BROW_R_MED": (0.0, 0.0, 0.0), "BROW_L_MED": (0.0, 0.0, 0.0), "LID_R_UP": (0.0, 0.0, 0.0),
    "LID_L_UP": (0.0, 0.0, 0.0), "MOUTH_R": (0.0, 0.0, 0.0), "MOUTH_L": (0.0, 0.0, 0.0),
    "LIP_UP": (0.0, 0.0, 0.0), "LIP_LOW": (0.0, 0.0, 0.0), "CHIN": (0.0, -6.0, 0.0),
    "CHEEK_R": (-20.0, -25.0, -40.0), "CHEEK_L": (20.0, -25.0, -40.0),
}
#: A layout unlike every preset (docs/howto/own-layout.md, "roles from motion"): :data:`LAYOUT` with the
#: brows up on the forehead, the mouth's markers wide and low and the chin under the jaw, so that no
#: preset's mouth corners lie near this layout's.
UNLIKE_PRESETS: dict[str, tuple[float, float, float]] = {
    **LAYOUT, "BROW_R_CEN": (-4.0, 14.0, -3.0), "BROW_L_CEN": (4.0, 14.0, -3.0), "BROW_R_MED": (-3.0, 16.0, -2.0),
    "BROW_L_MED": (3.0, 16.0, -2.0), "MOUTH_R": (-9.0, -6.0, -4.0), "MOUTH_L": (9.0, -6.0, -4.0),
    "CHIN": (0.0, -18.0, -10.0), "LIP_UP": (0.0, 6.0, -3.0), "LIP_LOW": (0.0, -5.0, -3.0),
}
#: The skull markers the head's pose is found from (toon32's head references).
SKULL = ("FOREHEAD", "TEMPLE_R", "TEMPLE_L", "NOSE_BRIDGE", "NOSE_TIP")
TURN_DEGREES, TILT_DEGREES = 140.0, 12.0
PLACE_M = np.array([0.4, -1.3, 1.5])


@dataclass(frozen=True)
class ForeignTake:
    """A take as another lab records it, and the truth about it.

    Attributes
    ----------
    take : Take
        Millimetres (as every take in memory), the camera system's frame, unlabelled columns in a
        seeded order.
    names : tuple of str
        Each column's toon32 name (the truth the take does not carry).
    axes : ndarray, shape (3, 3)
        Rows: the head frame's x (the performer's left), y (up) and z (out of the face) in the
        take's coordinates, at rest.
    """

    take: Take
    names: tuple[str, ...]
    axes: np.ndarray

    def write_csv(self, path: str | os.PathLike) -> Path:
        """The take as the lab's table: ``Unlabeled 1001_x,...`` columns in metres, no time column
        (the rate is the lab's to say), 6 decimals."""
        table = self.take.positions.reshape(self.take.frames, -1) / 1000.0
        header = ",".join(f"{label}_{axis}" for label in self.take.labels for axis in "xyz")
        text = header + "\n" + "\n".join(",".join("" if not np.isfinite(v) else f"{v:.6f}" for v in row)
                                         for row in table) + "\n"
        Path(path).write_text(text, encoding="utf-8")
        return Path(path)


def camera_turn() -> np.ndarray:
    """The head frame's axes as the camera system sees them, rows x, y, z: y onto the system's z
    (up), turned about it by :data:`TURN_DEGREES` and tilted about its x by :data:`TILT_DEGREES`."""
    z_up = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])  # rows: head x, y, z in the system
    a, b = np.radians(TURN_DEGREES), np.radians(TILT_DEGREES)
    turn = np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0], [0.0, 0.0, 1.0]])
    tilt = np.array([[1.0, 0.0, 0.0], [0.0, np.cos(b), -np.sin(b)], [0.0, np.sin(b), np.cos(b)]])
    return z_up @ turn.T @ tilt.T


def _poses(clean: Take) -> np.ndarray:
    """Per frame, the head's rotation ``(F, 3, 3)`` taking the head frame into the take's, from the
    skull markers (Kabsch against toon32's neutral)."""
    ms = load_markerset("toon32")
    ref = np.array([ms.neutral[ms.labels.index(n)] for n in SKULL])
    pos = clean.positions[:, [clean.labels.index(n) for n in SKULL]]
    return rigid_fit(ref, pos)[0]


def foreign_take(clean: Take, seed: int = 0, jitter_mm: float = 0.3,
                 layout: dict[str, tuple[float, float, float]] | None = None) -> ForeignTake:
    """``clean`` (a take of toon32 markers without sensor faults, mm) as another lab's take, its
    markers moved as ``layout`` says (:data:`LAYOUT` by default)."""
    rng = np.random.default_rng(seed)
    turns = _poses(clean)
    layout = LAYOUT if layout is None else layout
    names = tuple(layout)
    moved = np.stack([clean.positions[:, clean.labels.index(n)] + turns @ np.array(layout[n]) for n in names], axis=1)
    camera = camera_turn()
    world = moved @ camera + PLACE_M * 1000.0
    world = world + rng.normal(0.0, jitter_mm, world.shape)
    order = rng.permutation(len(names))
    labels = tuple(f"Unlabeled {1001 + k}" for k in range(len(names)))
    take = Take(world[:, order], labels, clean.rate, times=clean.times, meta={"source": "a foreign rig"})
    axes = turns[: max(1, int(clean.rate))].mean(axis=0).T @ camera  # rows: head axes in the system's frame
    u, _, vt = np.linalg.svd(axes)
    return ForeignTake(take, tuple(names[k] for k in order), u @ vt)
