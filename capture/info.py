"""What a take holds, for ``toonface info``: counts, rate, units and gaps per marker."""

from __future__ import annotations

import numpy as np

from capture.take import UNIT_MM, Take


def summarize(take: Take) -> dict:
    """A JSON-ready summary of ``take``.

    Returns
    -------
    dict
        ``frames``, ``markers``, ``rate`` (Hz), ``duration`` (seconds, first to last frame plus
        one frame), ``units`` (always ``"mm"``: every reader converts), ``dims``, ``labels``,
        ``missing`` (total missing marker-samples), ``missing_per_marker`` (label -> count, only
        markers with gaps), ``longest_gap`` (label -> frames), ``source`` (reader metadata) and
        ``channels`` (name -> ``{"min", "max", "measured"}``: the range of each channel, such as
        a markerless tracker's blendshape scores, and in how many frames it was measured).
    """
    missing = ~take.valid  # (frames, markers)
    per_marker = missing.sum(axis=0)
    duration = float(take.times[-1] - take.times[0] + 1.0 / take.rate) if take.frames else 0.0
    return {
        "frames": take.frames,
        "markers": take.markers,
        "rate": take.rate,
        "duration": duration,
        "units": "mm",
        "dims": take.dims,
        "labels": list(take.labels),
        "missing": int(missing.sum()),
        "missing_per_marker": {lab: int(n) for lab, n in zip(take.labels, per_marker, strict=True) if n},
        "longest_gap": {lab: _longest_run(missing[:, m]) for m, lab in enumerate(take.labels) if per_marker[m]},
        "source": dict(take.meta),
        "channels": {name: _channel_summary(take.channels[:, c]) for c, name in enumerate(take.channel_names)},
    }


def _channel_summary(values: np.ndarray) -> dict:
    seen = values[np.isfinite(values)]
    return {"min": round(float(seen.min()), 4) if seen.size else None,
            "max": round(float(seen.max()), 4) if seen.size else None, "measured": int(seen.size)}


def _longest_run(flags: np.ndarray) -> int:
    """Length of the longest run of ``True`` in a 1-D bool array."""
    padded = np.concatenate([[False], flags, [False]]).astype(np.int8)
    edges = np.flatnonzero(np.diff(padded))
    return int((edges[1::2] - edges[::2]).max()) if len(edges) else 0


def _as_read(units: object) -> str:
    """What the file's numbers were, where not millimetres (``info`` said "mm" for a take read
    with --units m: every take is held in millimetres, which is not what the file holds)."""
    if not isinstance(units, dict) or units.get("mm_per_unit") in (None, 1.0):
        return ""
    per = float(units["mm_per_unit"])
    name = next((unit for unit, mm in UNIT_MM.items() if mm == per), f"{per:g} mm units")
    return f" (the file's numbers in {name}, {units.get('from', 'given')}; held as mm)"


def describe(summary: dict) -> list[str]:
    """Human-readable lines of a :func:`summarize` result."""
    lines = [
        f"frames    {summary['frames']}",
        f"markers   {summary['markers']}",
        f"rate      {summary['rate']:g} Hz",
        f"duration  {summary['duration']:.3f} s",
        f"units     {summary['units']}{_as_read(summary['source'].get('units'))}",
        f"dims      {summary['dims']}",
        f"missing   {summary['missing']} marker-samples"
        + (f" in {len(summary['missing_per_marker'])} markers" if summary["missing"] else ""),
    ]
    source = summary["source"]
    if source.get("source"):
        extra = ", ".join(f"{k} {v}" for k, v in source.items()
                          if k in ("layout", "processor", "storage", "units_in_file", "analog_channels_skipped"))
        lines.append(f"source    {source['source']}" + (f" ({extra})" if extra else ""))
    if taken := source.get("defaults_from_markerset"):
        given = ", ".join(f"{k} {v}" for k, v in taken.items() if k != "markerset")
        lines.append(f"defaults  {given} (from marker set {taken['markerset']}: the table does not say)")
    for warning in source.get("warnings", []):
        lines.append(f"warning   {warning}")
    width = max((len(x) for x in summary["labels"]), default=6)
    lines.append("")
    lines.append(f"{'marker':<{width}}  missing  longest gap")
    for label in summary["labels"]:
        n = summary["missing_per_marker"].get(label, 0)
        gap = summary["longest_gap"].get(label, 0)
        lines.append(f"{label:<{width}}  {n:>7}  {gap:>11}")
    channels = summary.get("channels", {})
    if channels:
        width = max(len(x) for x in channels)
        lines += ["", f"{'channel':<{width}}  measured     min     max"]
        for name, c in channels.items():
            span = f"{c['min']:>7.3f} {c['max']:>7.3f}" if c["measured"] else f"{'-':>7} {'-':>7}"
            lines.append(f"{name:<{width}}  {c['measured']:>8} {span}")
    return lines
