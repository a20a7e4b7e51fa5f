"""Knot-point animations, as CharToon's Animation Editor makes them.

Each motor's motion is a list of knots ``(time, value)`` with linear interpolation between them
(before the first knot the motor holds its first value, after the last its last; a motor without
knots rests at the neutral). CharToon's knots are linear, and so are these by default; a knot
``(time, value, True)`` eases the segment that starts at it instead: slow out of the knot, slow
into the next, the smoothstep ``3u^2 - 2u^3`` of the way along (:func:`set_ease`). An animation
is sampled into a motor track at any rate. Editing works on a time slice ``[start, end)`` of
chosen motors: cut, copy, paste (also onto other motors, such as one brow's motion onto the
other), time scaling, value scaling and flipping; single knots are inserted, moved and deleted;
whole animations concatenate, with or without a cross-fade; a motor track becomes knots within a
tolerance (:func:`from_track`).

Files: TOML, ``format = "toonface.animation/1"``, ``duration`` in seconds and a ``[knots]`` table
of ``CODE = [[time, value], ...]``, an eased knot written ``[time, value, "ease"]``. A code beyond
the 21 is a face's parameter (``HT``...): it rests at its standard neutral
(:func:`toon.motors.extra_rest`) where it has no knots, and a sampled track carries it as an
extra column.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

from toon.motors import ALL_CODES, MOTOR_CODES, MOTOR_INDEX, extra_rest, standard_neutral
from toon.track import MotorTrack

FORMAT = "toonface.animation/1"
#: The longest animation, seconds (a day): what the reader takes and every edit may make.
MAX_DURATION = 86400.0
#: A knot: ``(time, value)``, or ``(time, value, True)`` where the segment from it to the next eases.
Knot = tuple[float, ...]
Knots = tuple[Knot, ...]
#: How an eased knot is written in a file (its third element).
EASE = "ease"
#: Linear pieces an eased segment becomes where an edit cuts it (each within 0.003 of the
#: segment's change of the curve: a slice's edge must not move the motion outside it).
BAKED_PIECES = 16


def eased(knot: Knot) -> bool:
    """Whether the segment that starts at ``knot`` eases."""
    return len(knot) > 2 and bool(knot[2])


def _at(knot: Knot, time: float, value: float | None = None) -> Knot:
    """``knot`` moved to ``time`` (and ``value``), keeping its ease."""
    v = knot[1] if value is None else value
    return (time, v, True) if eased(knot) else (time, v)


def smoothstep(u: np.ndarray) -> np.ndarray:
    """The ease between two knots: ``3u^2 - 2u^3`` of the way at ``u`` in [0, 1] of the time."""
    return u * u * (3.0 - 2.0 * u)


@dataclass(frozen=True)
class Animation:
    """Knots per motor and a length.

    Attributes
    ----------
    knots : dict of str to tuple of (time, value) or (time, value, True)
        Per motor code (or parameter beyond the 21), sorted by time; values in [0, 1]; a third
        element True eases the segment from that knot to the next.
    duration : float
        Seconds.
    """

    knots: dict[str, Knots] = field(default_factory=dict)
    duration: float = 0.0

    def value(self, code: str, t: np.ndarray | float, neutral: np.ndarray | None = None,
              declared: Mapping[str, float] | None = None) -> np.ndarray:
        """Motor or parameter ``code`` at times ``t`` (linear between knots, or eased where a knot
        says); without knots, its ``neutral`` (a parameter's: as ``declared`` by the face, else its
        standard rest)."""
        knots = self.knots.get(code)
        if not knots:
            if code not in MOTOR_INDEX:
                return np.full(np.shape(t), extra_rest(code, declared), dtype=float)
            rest = standard_neutral() if neutral is None else neutral
            return np.full(np.shape(t), rest[MOTOR_INDEX[code]], dtype=float)
        times, values = np.array([k[0] for k in knots]), np.array([k[1] for k in knots])
        at = np.array(t, dtype=float, ndmin=1)
        out = np.interp(at, times, values)
        for i in (i for i, k in enumerate(knots[:-1]) if eased(k) and knots[i + 1][0] > k[0]):
            inside = (at >= times[i]) & (at <= times[i + 1])
            u = (at[inside] - times[i]) / (times[i + 1] - times[i])
            out[inside] = values[i] + (values[i + 1] - values[i]) * smoothstep(u)
        return out.reshape(np.shape(t)) if np.ndim(t) else out[0]

    @property
    def extra_codes(self) -> tuple[str, ...]:
        """The parameters beyond the 21 that have knots: the standard ones in their order, then others."""
        return tuple(sorted((c for c in self.knots if c not in MOTOR_INDEX), key=code_order))

    def sample(self, rate: float, neutral: np.ndarray | None = None,
               declared: Mapping[str, float] | None = None) -> MotorTrack:
        """The animation as a motor track at ``rate`` frames per second (the movie script), its
        parameters beyond the 21 as extra columns."""
        frames = max(1, int(round(self.duration * rate)))  # a track of this duration (frames / rate)
        t = np.arange(frames) / rate
        values = np.column_stack([self.value(code, t, neutral) for code in MOTOR_CODES])
        codes = self.extra_codes
        extra = np.column_stack([self.value(code, t, declared=declared) for code in codes]) if codes else None
        return MotorTrack(values, rate, meta={"source": "animation"}, extra_codes=codes, extra=extra)


def code_order(code: str) -> tuple[int, str]:
    """Where ``code`` goes among an animation's: the 21 motors in order, the standard parameters
    beyond them in theirs, then any other by name."""
    return (ALL_CODES.index(code) if code in ALL_CODES else len(ALL_CODES), code)


def from_track(track: MotorTrack, tolerance: float = 0.01) -> Animation:
    """A motor track as knots: for each motor, as few of its samples as keep every sample within
    ``tolerance`` (of the 0..1 range) of the straight lines between them (Douglas and Peucker's
    simplification on the values); a motor that never leaves the standard neutral gets none.

    The animation starts at the track's first frame and lasts as long as the track.
    """
    if not tolerance > 0:
        raise ValueError(f"the tolerance must be > 0, got {tolerance}")
    times = np.arange(track.frames) / track.rate
    rest = np.concatenate([standard_neutral(), [extra_rest(c) for c in track.extra_codes]])
    table = track.table()
    knots: dict[str, Knots] = {}
    for i, code in enumerate((*MOTOR_CODES, *track.extra_codes)):
        values = np.clip(np.asarray(table[:, i], dtype=np.float64), 0.0, 1.0)
        if not np.isfinite(values).all():
            raise ValueError(f"motor {code} has unset values: fill or map the track first")
        if np.all(np.abs(values - rest[i]) <= 1e-12):
            continue
        kept = simplified_knots(times, values, tolerance)
        knots[code] = tuple((float(times[k]), float(values[k])) for k in kept)
    return Animation(knots, float(track.frames / track.rate))


def simplified_knots(times: np.ndarray, values: np.ndarray, tolerance: float) -> list[int]:
    """Indices of the samples ``(N,)`` Douglas-Peucker keeps within ``tolerance`` (vertical
    distance to each chord), the first and last included."""
    keep = {0, len(values) - 1}
    spans = [(0, len(values) - 1)]
    while spans:
        first, last = spans.pop()
        if last - first < 2:
            continue
        inner = np.arange(first + 1, last)
        share = (times[inner] - times[first]) / (times[last] - times[first])
        miss = np.abs(values[inner] - (values[first] + share * (values[last] - values[first])))
        worst = int(np.argmax(miss))
        if miss[worst] > tolerance:
            split = int(inner[worst])
            keep.add(split)
            spans += [(first, split), (split, last)]
    return sorted(keep)


def _edit(anim: Animation, codes: tuple[str, ...] | None, change, duration: float | None = None,
          edges: tuple[float, float] | None = None) -> Animation:
    """Apply ``change`` to each motor's knot list; with ``edges`` (a slice), knots are first added
    at both ends of the slice, so that a change inside it leaves the motion outside it as it was.

    Knots are kept in time order; two knots at one time make a step (the later one holds from
    that time on), which is what a slice edited apart from its surroundings leaves at its ends.
    """
    knots = dict(anim.knots)
    for code in codes or tuple(knots):
        old = list(knots.get(code, ()))
        if edges is not None and old:
            old = _with_edges(old, *edges, lambda x, c=code: float(anim.value(c, x)))
        new = _dedupe(sorted(change(old), key=lambda knot: knot[0]))  # stable: steps keep their order
        if new:
            knots[code] = tuple(new)
        else:
            knots.pop(code, None)
    return Animation(knots, anim.duration if duration is None else duration)


def _with_edges(knots: list, start: float, end: float, value_at) -> list:
    """``knots`` with a knot at ``start`` and at ``end`` (the values there) where there is none
    (an eased segment cut there becomes linear pieces along its curve first: :func:`_bake`)."""
    knots = _bake(knots, (start, end))
    times = {k[0] for k in knots}
    added = [(x, value_at(x)) for x in (start, end) if x not in times]
    return sorted(knots + added, key=lambda knot: knot[0])


def _bake(knots: list, cuts: tuple[float, ...]) -> list:
    """``knots`` with each eased segment that a time of ``cuts`` falls strictly inside made
    :data:`BAKED_PIECES` linear pieces along its curve: a cut there leaves the motion as it was
    (within 0.003 of the segment's change), which a new knot on an eased segment would not."""
    out: list = []
    for k, after in zip(knots, [*knots[1:], None], strict=True):
        if after is not None and eased(k) and any(k[0] < c < after[0] for c in cuts):
            u = np.arange(BAKED_PIECES) / BAKED_PIECES
            out += [(float(k[0] + (after[0] - k[0]) * x), float(k[1] + (after[1] - k[1]) * s))
                    for x, s in zip(u, smoothstep(u), strict=True)]
        else:
            out.append(k)
    return out


def _dedupe(knots: list) -> list:
    """Drop a knot that repeats the one before it (same time and value), and the middle of three
    or more at one time (a slice squeezed to nothing): a step keeps where it comes from and
    where it goes, which is all a file may hold."""
    out: list = []
    for knot in knots:
        if out and knot == out[-1]:
            continue
        if len(out) >= 2 and out[-1][0] == out[-2][0] == knot[0]:
            out[-1] = knot
            continue
        out.append(knot)
    return out


def _slice(knots: list, start: float, end: float, value_at) -> list:
    """The knots inside ``[start, end]`` with knots added at both ends (the values there; the
    first keeps the ease of a knot already at ``start``)."""
    baked = _bake(knots, (start, end))
    inside = [k for k in baked if start < k[0] < end]
    there = [k for k in baked if k[0] == start]
    first = _at(there[-1], start, value_at(start)) if there else (start, value_at(start))
    return [first, *inside, (end, value_at(end))]


def insert_knot(anim: Animation, code: str, time: float, value: float) -> Animation:
    """A knot for ``code`` at ``time`` (clipped to [0, duration]) with ``value`` (clipped to
    [0, 1]); one already at that time takes the new value (and keeps its ease). One put inside an
    eased segment eases on to the next knot, as the segment did. The duration is kept."""
    t, v = _knot(anim, time, value)
    old = anim.knots.get(code, ())
    same = [k for k in old if k[0] == t]
    within = [k for k in old if k[0] < t]
    ease = eased(same[-1]) if same else bool(within) and eased(within[-1]) and any(k[0] > t for k in old)
    knots = [k for k in old if k[0] != t]
    return _edit(anim, (code,), lambda _: sorted([*knots, (t, v, True) if ease else (t, v)]))


def move_knot(anim: Animation, code: str, index: int, time: float, value: float) -> Animation:
    """Knot ``index`` of ``code`` moved to ``time`` and ``value``: the time is kept between its
    neighbours' (knots keep their order, as in CharToon's editor), the value within [0, 1]."""
    knots = list(anim.knots.get(code, ()))
    if not 0 <= index < len(knots):
        raise IndexError(f"{code} has no knot {index} (it has {len(knots)})")
    t, v = _knot(anim, time, value)
    low = knots[index - 1][0] if index > 0 else 0.0
    high = knots[index + 1][0] if index + 1 < len(knots) else anim.duration
    knots[index] = _at(knots[index], min(max(t, low), high), v)
    if any(a[0] == b[0] == c[0] for a, b, c in zip(knots, knots[1:], knots[2:], strict=False)):
        raise ValueError(f"{code} would have three knots at {knots[index][0]:g} s (two make a step; three cannot)")
    return _edit(anim, (code,), lambda _: knots)


def delete_knot(anim: Animation, code: str, index: int) -> Animation:
    """Knot ``index`` of ``code`` removed (a motor left without knots rests at the neutral)."""
    knots = list(anim.knots.get(code, ()))
    if not 0 <= index < len(knots):
        raise IndexError(f"{code} has no knot {index} (it has {len(knots)})")
    return _edit(anim, (code,), lambda _: knots[:index] + knots[index + 1:])


def set_ease(anim: Animation, code: str, index: int, ease: bool) -> Animation:
    """The segment from knot ``index`` of ``code`` to the next eased (slow out, slow in) or
    linear again. The last knot starts no segment: a ValueError."""
    knots = list(anim.knots.get(code, ()))
    if not 0 <= index < len(knots):
        raise IndexError(f"{code} has no knot {index} (it has {len(knots)})")
    if index == len(knots) - 1:
        raise ValueError(f"{code}'s last knot starts no segment to ease")
    t, v = knots[index][:2]
    knots[index] = (t, v, True) if ease else (t, v)
    return _edit(anim, (code,), lambda _: knots)


def _knot(anim: Animation, time: float, value: float) -> tuple[float, float]:
    if not (np.isfinite(time) and np.isfinite(value)):
        raise ValueError(f"a knot needs a finite time and value, got ({time}, {value})")
    return float(min(max(time, 0.0), anim.duration)), float(min(max(value, 0.0), 1.0))


def copy(anim: Animation, codes: tuple[str, ...], start: float, end: float) -> Animation:
    """The slice ``[start, end]`` of ``codes`` as a clip starting at time 0."""
    clip = {c: tuple(_at(k, k[0] - start) for k in _slice(list(anim.knots.get(c, ())), start, end,
                                                          lambda x, c=c: float(anim.value(c, x))))
            for c in codes}
    return Animation(clip, end - start)


def cut(anim: Animation, codes: tuple[str, ...], start: float, end: float) -> tuple[Animation, Animation]:
    """Remove the slice from ``codes`` (later knots move earlier by its length); returns the
    edited animation and the clip (as :func:`copy`)."""
    clip, span = copy(anim, codes, start, end), end - start

    def change(knots: list) -> list:
        before = [k for k in knots if k[0] < start]
        after = [_at(k, k[0] - span) for k in knots if k[0] > end]
        return before + after
    return _edit(anim, codes, change), clip


def paste(anim: Animation, clip: Animation, at: float, onto: dict[str, str] | None = None) -> Animation:
    """Put ``clip`` at time ``at``, replacing what was there for its length; ``onto`` maps clip
    motors to the motors that receive them (default: the same ones)."""
    onto = onto or {c: c for c in clip.knots}
    knots = dict(anim.knots)
    for source, target in onto.items():
        keep = [k for k in knots.get(target, ()) if k[0] < at or k[0] > at + clip.duration]
        knots[target] = tuple(sorted(keep + [_at(k, at + k[0]) for k in clip.knots.get(source, ())]))
    return Animation(knots, max(anim.duration, at + clip.duration))


def scale_time(anim: Animation, codes: tuple[str, ...] | None, start: float, end: float, factor: float) -> Animation:
    """Stretch the slice by ``factor`` (knots after it move accordingly)."""
    if factor <= 0:
        raise ValueError(f"time factor must be > 0, got {factor}")
    shift = (end - start) * (factor - 1)

    def change(knots: list) -> list:
        return [_at(k, k[0] if k[0] <= start else start + (k[0] - start) * factor if k[0] <= end else k[0] + shift)
                for k in knots]
    return _edit(anim, codes, change, anim.duration + shift, edges=(start, end))


def scale_value(anim: Animation, codes: tuple[str, ...] | None, start: float, end: float, factor: float,
                neutral: np.ndarray | None = None) -> Animation:
    """Scale values in the slice about each motor's neutral by ``factor`` (clipped to [0, 1])."""
    rest = standard_neutral() if neutral is None else neutral

    def change_for(code: str):
        pivot = rest[MOTOR_INDEX[code]] if code in MOTOR_INDEX else extra_rest(code)
        return lambda knots: _in_slice(knots, start, end, anim.duration, lambda inside: [
            _at(k, k[0], float(np.clip(pivot + (k[1] - pivot) * factor, 0, 1))) for k in inside])
    out = anim
    for code in codes or tuple(anim.knots):
        out = _edit(out, (code,), change_for(code), edges=(start, end))
    return out


def flip(anim: Animation, codes: tuple[str, ...] | None, start: float, end: float) -> Animation:
    """Reverse the slice in time (the motion played backwards within it; an eased segment stays
    eased, the ease being the same either way)."""
    def backwards(inside: list) -> list:
        out = []
        for j, k in enumerate(reversed(inside)):  # segment j runs from this knot to the one before it
            t = start + end - k[0]
            out.append((t, k[1], True) if j + 1 < len(inside) and eased(inside[-j - 2]) else (t, k[1]))
        return out
    return _edit(anim, codes, lambda knots: _in_slice(knots, start, end, anim.duration, backwards),
                 edges=(start, end))


def _in_slice(knots: list, start: float, end: float, duration: float, change) -> list:
    """``knots`` (with knots at ``start`` and ``end``) with ``change`` applied to those in the
    slice; the values at its ends outside it are kept, making a step where they differ."""
    before = [k for k in knots if k[0] < start]
    inside = [k for k in knots if start <= k[0] <= end]
    after = [k for k in knots if k[0] > end]
    if len(inside) > 1 and inside[0][0] == inside[1][0] == start:  # a step at an end: its outer knot is
        before.append(inside.pop(0))  # the motion outside the slice, left as it is
    if len(inside) > 1 and inside[-1][0] == inside[-2][0] == end:
        after.insert(0, inside.pop())
    # The values at the slice's ends stay outside it, where there is motion outside (knots, or a
    # motor held before its first knot or after its last); a step already there keeps them.
    edge_in = [inside[0]] if (before or start > 0) and not (before and before[-1][0] == start) else []
    edge_out = [inside[-1]] if (after or end < duration) and not (after and after[0][0] == end) else []
    return [*before, *edge_in, *change(inside), *edge_out, *after]


def concatenate(first: Animation, second: Animation, fade: float = 0.0) -> Animation:
    """``second`` after ``first``; with ``fade`` seconds, they overlap that long and the motion
    blends linearly from the first into the second."""
    if fade < 0 or fade > min(first.duration, second.duration):
        raise ValueError(f"fade must be 0..{min(first.duration, second.duration):g} s, got {fade}")
    offset = first.duration - fade
    codes = sorted(set(first.knots) | set(second.knots), key=code_order)
    knots = {}
    for code in codes:
        a = [k for k in first.knots.get(code, ()) if k[0] < offset]
        b = [_at(k, offset + k[0]) for k in second.knots.get(code, ()) if k[0] > fade or fade == 0]
        blend = []
        if fade > 0:
            times = sorted({offset, first.duration} | {k[0] for k in first.knots.get(code, ()) if k[0] >= offset}
                           | {offset + k[0] for k in second.knots.get(code, ()) if k[0] <= fade})
            for t in times:
                w = (t - offset) / fade
                blend.append((t, float((1 - w) * first.value(code, t) + w * second.value(code, t - offset))))
        merged = {k[0]: k for k in a + blend + b}  # one knot a time: the later of two
        knots[code] = tuple(merged[t] for t in sorted(merged))
    return Animation(knots, offset + second.duration)
