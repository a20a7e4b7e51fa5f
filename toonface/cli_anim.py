"""``toonface anim``: knot-point animations (CharToon's Animation Editor) edited as files."""

from __future__ import annotations

import dataclasses
import math

import click

from toon import animation as an
from toon import animation_file as af
from toon.animation import Animation
from toonface.cli_options import FiniteFloat, parse_codes


def _slice_options(fn):
    fn = click.option("--to", "end", type=FiniteFloat(), default=None,
                      help="Slice end, seconds [default: the end].")(fn)
    fn = click.option("--from", "start", type=FiniteFloat(), default=0.0, show_default=True,
                      help="Slice start, seconds.")(fn)
    return click.option("--motors", default=None, metavar="CODE,...", help="Motors to edit [default: all].")(fn)


def _span(anim: Animation, start: float, end: float | None) -> tuple[float, float]:
    end = anim.duration if end is None else min(end, anim.duration)  # a slice past the end stops there
    if not 0 <= start < end:
        raise click.BadParameter(f"expected 0 <= --from < --to, got {start:g}, {end:g}", param_hint="--from/--to")
    return start, end


@click.group()
def anim() -> None:
    """Knot-point animations (CharToon's Animation Editor) on files.

    An animation (TOML, toonface.animation/1) holds knots [time, value] per motor, joined by
    straight lines. Edit a slice of chosen motors, then sample it into a motor track or render
    it: `toonface render walk.toml -o walk.mp4`.
    """


@anim.command("sample")
@click.argument("animation", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False), help="Motor track (.csv or .npz).")
@click.option("--rate", default=30.0, show_default=True, type=FiniteFloat(1, 1000), help="Frames per second.")
def anim_sample(animation: str, output: str, rate: float) -> None:
    """Sample an animation into a motor track (a movie script)."""
    from toon import save_track

    track = af.load_animation(animation).sample(rate)
    click.echo(f"wrote {save_track(track, output)} ({track.frames} frames at {rate:g} Hz)")


@anim.command("cut")
@click.argument("animation", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False))
@click.option("--clip", "clip_path", default=None, type=click.Path(dir_okay=False), help="Also save what was cut.")
@_slice_options
def anim_cut(animation: str, output: str, clip_path: str | None, motors: str | None, start: float,
             end: float | None) -> None:
    """Cut a slice out of chosen motors; what follows moves earlier."""
    source = af.load_animation(animation)
    codes = parse_codes(motors, also=tuple(source.knots)) or tuple(source.knots)
    edited, clip = an.cut(source, codes, *_span(source, start, end))
    af.save_animation(edited, output)
    if clip_path:
        af.save_animation(clip, clip_path)
    click.echo(f"wrote {output}" + (f" and {clip_path}" if clip_path else ""))


@anim.command("copy")
@click.argument("animation", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False), help="The clip.")
@_slice_options
def anim_copy(animation: str, output: str, motors: str | None, start: float, end: float | None) -> None:
    """Copy a slice of chosen motors into a clip (itself an animation starting at 0)."""
    source = af.load_animation(animation)
    codes = parse_codes(motors, also=tuple(source.knots)) or tuple(source.knots)
    af.save_animation(an.copy(source, codes, *_span(source, start, end)), output)
    click.echo(f"wrote {output}")


@anim.command("paste")
@click.argument("animation", type=click.Path(dir_okay=False))
@click.argument("clip", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False))
@click.option("--at", type=FiniteFloat(min=0), required=True, help="Where the clip starts, seconds.")
@click.option("--onto", default=None, metavar="FROM=TO,...",
              help="Put clip motors onto other motors, e.g. BRL=BLL,BRC=BLC,BRM=BLM [default: the same].")
def anim_paste(animation: str, clip: str, output: str, at: float, onto: str | None) -> None:
    """Paste a clip at a time, replacing what was there for its length."""
    pairs = None
    target, source = af.load_animation(animation), af.load_animation(clip)
    if onto:
        try:
            pairs = dict(p.split("=") for p in onto.upper().split(","))
        except ValueError:
            raise click.BadParameter(f"expected FROM=TO pairs, got {onto!r}", param_hint="--onto") from None
        parse_codes(",".join([*pairs, *pairs.values()]), "--onto", also=(*target.knots, *source.knots))
    af.save_animation(an.paste(target, source, at, pairs), output)
    click.echo(f"wrote {output}")


@anim.command("scale")
@click.argument("animation", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False))
@click.option("--time", "time_factor", default=1.0, show_default=True, type=FiniteFloat(min=0, min_open=True),
              help="Stretch the slice in time by this factor.")
@click.option("--value", "value_factor", default=1.0, show_default=True, type=FiniteFloat(),
              help="Scale values about neutral by this factor.")
@_slice_options
def anim_scale(animation: str, output: str, time_factor: float, value_factor: float, motors: str | None,
               start: float, end: float | None) -> None:
    """Scale a slice of chosen motors in time and/or in value."""
    out = af.load_animation(animation)
    span = _span(out, start, end)
    codes = parse_codes(motors, also=tuple(out.knots))
    if value_factor != 1.0:
        out = an.scale_value(out, codes, *span, value_factor)
    if time_factor != 1.0:
        out = an.scale_time(out, codes, *span, time_factor)
    af.save_animation(out, output)
    click.echo(f"wrote {output} ({out.duration:g} s)")


@anim.command("flip")
@click.argument("animation", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False))
@_slice_options
def anim_flip(animation: str, output: str, motors: str | None, start: float, end: float | None) -> None:
    """Play a slice of chosen motors backwards."""
    source = af.load_animation(animation)
    af.save_animation(an.flip(source, parse_codes(motors, also=tuple(source.knots)), *_span(source, start, end)),
                      output)
    click.echo(f"wrote {output}")


@anim.command("from-track")
@click.argument("track", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False), help="Animation (.toml).")
@click.option("--tolerance", default=0.01, show_default=True, type=FiniteFloat(min=0, min_open=True),
              help="How far (of the 0..1 range) the lines between knots may stray from the track's values.")
def anim_from_track(track: str, output: str, tolerance: float) -> None:
    """Turn a motor track (.csv, .npz) into knots to edit: as few as keep every value within the tolerance."""
    from toon import load_track

    motors = load_track(track)  # its parameters beyond the 21 (HT...) become knots too
    try:
        out = an.from_track(motors, tolerance)
    except ValueError as exc:
        raise click.BadParameter(f"{track}: {exc}", param_hint="TRACK") from None
    af.save_animation(out, output)
    click.echo(f"wrote {output} ({sum(len(k) for k in out.knots.values())} knots for {motors.frames} frames)")


@anim.command("knot")
@click.argument("animation", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False))
@click.option("--motor", required=True, metavar="CODE", help="The motor whose knots change, e.g. MB.")
@click.option("--add", default=None, metavar="TIME,VALUE", help="Insert a knot (one at that time takes the value).")
@click.option("--move", default=None, metavar="INDEX:TIME,VALUE",
              help="Move knot INDEX (0 is the first); it stays between its neighbours.")
@click.option("--delete", default=None, type=click.IntRange(min=0), metavar="INDEX", help="Delete knot INDEX.")
@click.option("--ease", default=None, type=click.IntRange(min=0), metavar="INDEX",
              help="Ease the segment from knot INDEX to the next: slow out of it, slow into the next.")
@click.option("--linear", default=None, type=click.IntRange(min=0), metavar="INDEX",
              help="Make the segment from knot INDEX to the next linear again (the default).")
@click.option("--new", "new_parameter", is_flag=True,
              help="--motor is a face's own parameter that this animation has no knots for yet (else a code that "
                   "is not one of the 21, a standard parameter or the animation's own is refused as a typo).")
def anim_knot(animation: str, output: str, motor: str, add: str | None, move: str | None, delete: int | None,
              ease: int | None, linear: int | None, new_parameter: bool) -> None:
    """Insert, move or delete one knot of one motor, or ease the segment from it to the next or
    make it linear again (one of --add, --move, --delete, --ease, --linear). Knots are joined by
    straight lines unless eased, as CharToon's are. A knot added or moved past the animation's
    end makes it longer, and says so."""

    if sum(x is not None for x in (add, move, delete, ease, linear)) != 1:
        raise click.UsageError("give one of --add, --move, --delete, --ease and --linear")
    source = af.load_animation(animation)
    codes = parse_codes(motor, "--motor", also=tuple(source.knots), any_parameter=new_parameter)
    if not codes or len(codes) != 1:
        raise click.BadParameter(f"expected one motor code, got {motor!r}", param_hint="--motor")
    code = codes[0]
    try:
        if add is not None:
            time, value = _pair(add, "--add")
            out = an.insert_knot(_longer(source, time), code, time, value)
        elif move is not None:
            index, _, rest = move.partition(":")
            if not index.isdigit():
                raise click.BadParameter(f"expected INDEX:TIME,VALUE, got {move!r}", param_hint="--move")
            time, value = _pair(rest, "--move")
            out = an.move_knot(_longer(source, time), code, int(index), time, value)
        elif delete is not None:
            out = an.delete_knot(source, code, delete)
        else:
            which = ease if ease is not None else linear
            assert which is not None
            out = an.set_ease(source, code, which, ease is not None)
    except (IndexError, ValueError) as exc:
        raise click.BadParameter(str(exc), param_hint="--add/--move/--delete/--ease/--linear") from None
    af.save_animation(out, output)
    click.echo(f"wrote {output} ({len(out.knots.get(code, ()))} knots on {code})")


def _pair(text: str, option: str) -> tuple[float, float]:
    try:
        time, value = (float(x) for x in text.split(","))
    except ValueError:
        raise click.BadParameter(f"expected TIME,VALUE, got {text!r}", param_hint=option) from None
    if not (math.isfinite(time) and math.isfinite(value)) or time < 0:
        raise click.BadParameter(f"expected a TIME of 0 s or more and a finite VALUE, got {text!r}", param_hint=option)
    return time, value


def _longer(anim: Animation, time: float) -> Animation:
    """``anim``, made as long as ``time`` where a knot goes past its end (said on stderr)."""
    if time <= anim.duration:
        return anim
    if time > af.MAX_DURATION:
        raise click.BadParameter(f"a knot at {time:g} s: an animation lasts {af.MAX_DURATION:g} s at most",
                                 param_hint="--add/--move")
    click.echo(f"note: the animation is now {time:g} s long (was {anim.duration:g} s): a knot at {time:g} s",
               err=True)
    return dataclasses.replace(anim, duration=time)


@anim.command("concat")
@click.argument("animations", nargs=-1, required=True, type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False))
@click.option("--fade", default=0.0, show_default=True, type=FiniteFloat(min=0),
              help="Cross-fade seconds between one and the next.")
def anim_concat(animations: tuple[str, ...], output: str, fade: float) -> None:
    """Join animations one after another, optionally cross-fading."""
    out = af.load_animation(animations[0])
    for path in animations[1:]:
        try:
            out = an.concatenate(out, af.load_animation(path), fade)
        except ValueError as exc:
            raise click.BadParameter(str(exc), param_hint="--fade") from None
    af.save_animation(out, output)
    click.echo(f"wrote {output} ({out.duration:g} s)")


ANIM_COMMANDS = (anim,)
