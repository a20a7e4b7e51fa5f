"""``Take``: marker trajectories, the output of every capture source."""

from __future__ import annotations

from collections import Counter
from dataclasses import dataclass, field, replace

import numpy as np

from common import InputError, readonly

#: The channel that holds a take's sound level at each frame (1: its loudest), where it had sound.
SOUND_LEVEL = "sound_level"
#: No marker lies further than this from its take's origin (mm): a kilometre.
MAX_POSITION_MM = 1e6
#: Millimetres per unit, for the unit names take files use (C3D POINT:UNITS, TRC Units, --units).
UNIT_MM = {"mm": 1.0, "millimeters": 1.0, "millimetres": 1.0, "cm": 10.0, "m": 1000.0, "meters": 1000.0,
           "metres": 1000.0, "in": 25.4, "inch": 25.4, "inches": 25.4}


@dataclass(frozen=True, eq=False)
class Take:
    """Marker positions over time.

    Parameters
    ----------
    positions : array_like, shape (frames, markers, 3)
        Millimetres; NaN where a marker was not seen (all three coordinates together).
        2-D sources fill z with 0 and set ``dims=2``.
    labels : sequence of str, length markers
        Unique marker names.
    rate : float
        Frames per second.
    times : array_like, shape (frames,), optional
        Seconds, strictly increasing; defaults to ``frame / rate``.
    dims : int
        3, or 2 for planar sources.
    meta : dict
        Free-form provenance (source file, vendor, ...).
    channels : array_like, shape (frames, channels), optional
        Scalar measurements a tracker reports beside the markers, one column per name in
        ``channel_names`` (a markerless tracker's blendshape scores, 0..1); NaN where not
        measured. None: no channels.
    channel_names : sequence of str
        Unique names of ``channels``' columns (``jawOpen``, ``eyeBlinkLeft``, ...).
    """

    positions: np.ndarray
    labels: tuple[str, ...]
    rate: float
    times: np.ndarray = None  # type: ignore[assignment]  # None: frame / rate; __post_init__ stores an array
    dims: int = 3
    meta: dict = field(default_factory=dict)
    channels: np.ndarray = None  # type: ignore[assignment]  # None: no channels; __post_init__ stores an array
    channel_names: tuple[str, ...] = ()
    _columns: dict[str, int] = field(init=False, repr=False, default_factory=dict)  # label -> column, for index

    def __post_init__(self) -> None:
        pos = np.asarray(self.positions, dtype=np.float64)
        if pos.ndim != 3 or pos.shape[2] != 3:
            raise InputError(f"positions must have shape (frames, markers, 3), got {pos.shape}")
        labels = tuple(str(x) for x in self.labels)
        if len(labels) != pos.shape[1]:
            raise InputError(f"{len(labels)} labels for {pos.shape[1]} markers")
        dupes = sorted(x for x, n in Counter(labels).items() if n > 1)  # linear: tables may have 100k columns
        if dupes:
            raise InputError(f"marker labels must be unique; repeated: {dupes}")
        if not (np.isfinite(self.rate) and self.rate > 0):
            raise InputError(f"rate must be a positive number of frames per second, got {float(self.rate):g}")
        if self.dims not in (2, 3):
            raise InputError(f"dims must be 2 or 3, got {self.dims!r}")
        if np.isinf(pos).any():
            raise InputError("positions contain infinities; use NaN for unseen markers")
        far = np.nanmax(np.abs(pos), initial=0.0)
        if far > MAX_POSITION_MM:  # 1e308 in a take overflowed every sum downstream
            raise InputError(f"a position of {far:.3g} mm: markers lie within {MAX_POSITION_MM:g} mm (a kilometre) of "
                             "the origin; are these markers in millimetres?")
        pos = pos.copy()
        pos[np.isnan(pos).any(axis=2)] = np.nan  # a marker is seen in all coordinates or none
        times = np.arange(pos.shape[0]) / float(self.rate) if self.times is None else np.asarray(self.times, float)
        if times.shape != (pos.shape[0],):
            raise InputError(f"times must have shape ({pos.shape[0]},), got {times.shape}")
        if times.size > 1 and not np.all(np.diff(times) > 0):
            raise InputError("times must be strictly increasing")
        object.__setattr__(self, "positions", readonly(pos))
        object.__setattr__(self, "labels", labels)
        object.__setattr__(self, "_columns", {label: i for i, label in enumerate(labels)})
        object.__setattr__(self, "rate", float(self.rate))
        object.__setattr__(self, "times", readonly(times))
        self._check_channels(pos.shape[0])

    def _check_channels(self, frames: int) -> None:
        names = tuple(str(x) for x in self.channel_names)
        channels = (np.empty((frames, 0)) if self.channels is None and not names
                    else np.asarray(self.channels, dtype=np.float64))
        if channels.shape != (frames, len(names)):
            raise InputError(f"channels must have shape ({frames}, {len(names)}) for {len(names)} channel names, "
                             f"got {channels.shape}")
        if len(set(names)) != len(names):
            repeated = sorted(x for x, n in Counter(names).items() if n > 1)
            raise InputError(f"channel names must be unique; repeated: {repeated}")
        if np.isinf(channels).any():
            raise InputError("channels contain infinities; use NaN for values not measured")
        object.__setattr__(self, "channels", readonly(channels.copy()))
        object.__setattr__(self, "channel_names", names)

    @property
    def frames(self) -> int:
        """Number of frames."""
        return self.positions.shape[0]

    @property
    def markers(self) -> int:
        """Number of markers."""
        return self.positions.shape[1]

    @property
    def valid(self) -> np.ndarray:
        """Where each marker was seen, bool ``(frames, markers)``."""
        return ~np.isnan(self.positions[:, :, 0])

    def index(self, label: str) -> int:
        """Column of a marker; raises :class:`InputError` naming the missing label."""
        column = self._columns.get(label)
        if column is None:
            raise InputError(f'no marker "{label}" in this take')
        return column

    def marker(self, label: str) -> np.ndarray:
        """One marker's trajectory, shape ``(frames, 3)``."""
        return self.positions[:, self.index(label)]

    def select(self, labels: list[str] | tuple[str, ...]) -> np.ndarray:
        """Several markers' trajectories in the given order, shape ``(frames, len(labels), 3)``."""
        return self.positions[:, [self.index(x) for x in labels]]

    def channel(self, name: str) -> np.ndarray:
        """One channel's values, shape ``(frames,)``; raises :class:`InputError` naming a missing one."""
        if name not in self.channel_names:
            raise InputError(f'no channel "{name}" in this take')
        return self.channels[:, self.channel_names.index(name)]

    def window(self, start: float, end: float) -> np.ndarray:
        """Boolean frame mask for times in ``[start, end)`` seconds, shape ``(frames,)``."""
        return np.asarray((self.times >= start) & (self.times < end))

    def part(self, start: float | None = None, end: float | None = None) -> Take:
        """The frames with times in ``[start, end)`` seconds (None: from the first, to the last),
        their times as they were; raises :class:`InputError` where no frame is in it."""
        low = -np.inf if start is None else start
        high = np.inf if end is None else end
        if high <= low:
            raise InputError(f"the end ({high:g} s) must come after the start ({low:g} s)")
        kept = self.window(low, high)
        if not kept.any():
            raise InputError(f"no frame between {low:g} and {high:g} s: the take runs "
                             f"{self.times[0]:g}-{self.times[-1]:g} s")
        return replace(self, positions=self.positions[kept], times=self.times[kept],
                       channels=self.channels[kept])


def unique_labels(labels: list[str]) -> tuple[tuple[str, ...], dict[str, str]]:
    """Trimmed labels made unique: empty ones named ``M001``..., repeats suffixed ``#2``, ``#3``...

    Returns the labels and, for each changed column, ``{new: original}``.
    """
    out: list[str] = []
    renamed: dict[str, str] = {}
    taken: set[str] = set()
    for i, raw in enumerate(labels):
        name = raw.strip() or f"M{i + 1:03d}"
        candidate, k = name, 1
        while candidate in taken:
            k += 1
            candidate = f"{name}#{k}"
        taken.add(candidate)
        out.append(candidate)
        if candidate != raw.strip():
            renamed[candidate] = raw
    return tuple(out), renamed
