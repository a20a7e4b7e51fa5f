"""C3D files with the quirks of other vendors' exports, written here (the c3d library's writer,
then the parameter section patched as those exporters write it), for the reader's tests.

Each writer makes a 30-frame, 100 Hz file of three markers A, B, C (A moves, B and C stand) and
returns its path; what is special is in each function's docstring.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import c3d
import numpy as np

FRAMES = 30


def _positions() -> np.ndarray:
    """(frames, 3 markers, 3) in mm."""
    t = np.arange(FRAMES) / 100.0
    a = np.column_stack([10 + 50 * t, 20 + 5 * np.sin(4 * t), np.full(FRAMES, 30.0)])
    return np.stack([a, np.tile([100.0, 0.0, 5.0], (FRAMES, 1)), np.tile([-40.0, 60.0, 7.0], (FRAMES, 1))], axis=1)


def _write(path: Path, labels: list[str], positions: np.ndarray, residuals: np.ndarray, edit=None,
           units: str = "mm  ") -> Path:
    writer = c3d.Writer(point_rate=100.0, analog_rate=0.0, point_scale=-1.0, point_units=units)
    writer.set_point_labels(labels)
    if edit is not None:
        edit(writer)
    frames = []
    for f in range(len(positions)):
        points = np.zeros((len(labels), 5), dtype=np.float32)
        points[:, :3] = positions[f]
        points[:, 3] = residuals[f]
        frames.append((points, np.empty((0, 0), dtype=np.float32)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        writer.add_frames(frames)
        with open(path, "wb") as fh:
            writer.write(fh)
    return path


def plain(path: Path) -> Path:
    """Nothing special: the reference the others are compared with."""
    return _write(path, ["A", "B", "C"], _positions(), np.zeros((FRAMES, 3)))


def units_in_rows(path: Path) -> Path:
    """POINT:UNITS as a 4 x 3 character array, "mm  mm  mm  ", as some exporters store it."""
    def edit(writer):
        writer.point_group.set_str("UNITS", "Units", "mm  mm  mm  ", 4, 3)
    return _write(path, ["A", "B", "C"], _positions(), np.zeros((FRAMES, 3)), edit)


def units_nul_padded(path: Path) -> Path:
    """POINT:UNITS "cm\\0\\0" (NUL bytes as padding, as three public files store it), centimetres."""
    return _write(path, ["A", "B", "C"], _positions() / 10.0, np.zeros((FRAMES, 3)), units="cm\0\0")


def units_padded(path: Path) -> Path:
    """POINT:UNITS " cm " (padded both sides) with the positions in centimetres."""
    return _write(path, ["A", "B", "C"], _positions() / 10.0, np.zeros((FRAMES, 3)), units=" cm ")


def duplicated_parameter(path: Path) -> Path:
    """A SUBJECTS group holding BODYMASS twice (as Vicon Plug-in Gait exports do)."""
    def edit(writer):
        group = writer.add_group(5, "SUBJECTS", "Subjects")
        group.add("BODYMASS", "Body mass", 4, "<f", 71.5)
        group.add("BODYMASX", "Body mass", 4, "<f", 71.5)
    _write(path, ["A", "B", "C"], _positions(), np.zeros((FRAMES, 3)), edit)
    data = path.read_bytes()
    assert data.count(b"BODYMASX") == 1
    path.write_bytes(data.replace(b"BODYMASX", b"BODYMASS"))
    return path


def zeros_for_gaps(path: Path) -> Path:
    """B missing in frames 10-19 written as x = y = z = 0 with a residual of 0 (not -1), as some
    exporters mark gaps; C genuinely at the origin's x = 0 in every frame."""
    positions = _positions()
    positions[10:20, 1] = 0.0
    positions[:, 2, 0] = 0.0
    return _write(path, ["A", "B", "C"], positions, np.zeros((FRAMES, 3)))


def plug_in_gait(path: Path) -> Path:
    """Three markers and four modelled outputs stored as points (Plug-in Gait): a knee angle, a
    hip force, moment and power, listed in POINT:ANGLES, FORCES, MOMENTS and POWERS."""
    labels = ["A", "B", "C", "LKneeAngles", "LHipForce", "LHipMoment", "LHipPower"]
    modelled = np.tile([[12.0, -3.0, 1.5], [0.5, 1.2, 8.0], [900.0, 40.0, -20.0], [1.0, 0.0, 0.0]], (FRAMES, 1, 1))
    positions = np.concatenate([_positions(), modelled], axis=1)

    def edit(writer):
        for name, label in (("ANGLES", "LKneeAngles"), ("FORCES", "LHipForce"), ("MOMENTS", "LHipMoment"),
                            ("POWERS", "LHipPower")):
            writer.point_group.add_str(name, f"{name.lower()} outputs", label, len(label), 1)
    return _write(path, labels, positions, np.zeros((FRAMES, len(labels))), edit)


QUIRKS = {"units_in_rows": units_in_rows, "units_padded": units_padded, "units_nul_padded": units_nul_padded,
          "duplicated_parameter": duplicated_parameter,
          "zeros_for_gaps": zeros_for_gaps, "plug_in_gait": plug_in_gait}
