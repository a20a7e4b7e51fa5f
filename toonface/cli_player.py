"""The player subcommands: play (the live Animator) and anim (knot-point animations)."""

from __future__ import annotations

import sys

import click

from player.animator import DEFAULT_LOOP_TIME
from toon import animation as an
from toon import animation_file as af
from toon.animation import Animation
from toonface.cli_options import (
    BACKGROUND,
    EYE_CONTACT,
    FACE,
    LIFE,
    NO_PHYSICS,
    OPENSEEFACE,
    SIZE,
    VIRTUAL_CAMERA,
    VMC,
    VMC_OUT,
    FiniteFloat,
    bridge_spec,
    parse_codes,
    parse_size,
    with_background,
    without_physics,
)


def _address(value: str | None, option: str, port: int) -> tuple[str, int] | None:
    """``HOST:PORT`` from an option (``port`` when only a host is given); None for ``off`` or no value."""
    if value is None or value.lower() == "off":
        return None
    return _required_address(value, option, port)


def _required_address(value: str, option: str, port: int) -> tuple[str, int]:
    """``HOST:PORT`` from an option that cannot be switched off."""
    from common.address import parse_address

    try:
        return parse_address(value, port)
    except ValueError as exc:
        raise click.BadParameter(str(exc), param_hint=option) from None


@click.command()
@FACE
@click.option("--listen", default="127.0.0.1:7707", show_default=True, metavar="HOST:PORT|off",
              help="TCP command socket (a reply per line). Port 0 picks a free one.")
@click.option("--udp", default=None, metavar="HOST:PORT", help="Also a UDP command socket (fire and forget).")
@click.option("--preview", default=None, metavar="HOST:PORT",
              help="Serve a live MJPEG preview for a browser, e.g. 127.0.0.1:8080.")
@click.option("-o", "--output", default=None, type=click.Path(),
              help="Also record: a .mp4 file, a folder for PNG frames, - for raw RGB on standard output, or "
                   "vcam:[DEVICE] for a virtual webcam.")
@click.option("--loop-ms", default=DEFAULT_LOOP_TIME * 1000, show_default=True, type=FiniteFloat(5, 1000),
              help="Loop time: one frame and one slice per moving motor per loop (ToonFace used 100).")
@SIZE
@BACKGROUND
@VIRTUAL_CAMERA
@click.option("--motors", "--track", "track_path", default=None, type=click.Path(dir_okay=False),
              help="Play a motor track (.csv movie script or .npz) at its own rate instead of commands.")
@click.option("--once", is_flag=True, help="With --motors, or a video or take file as --source: play it once "
                                          "(default: loop).")
@click.option("--source", "source_spec", default=None, metavar="SPEC",
              help="Drive the face from a performer, mapped live: camera:N, camera:VIDEO, face:VIDEO, a take "
                   "file or synthetic (as toonface send takes them).")
@click.option("--camera", default=None, metavar="N|VIDEO",
              help="The same as --source camera:N: a camera (or a video played as one) drives the face.")
@VMC
@OPENSEEFACE
@VMC_OUT
@click.option("--providers", "providers_path", default=None, type=click.Path(dir_okay=False),
              help="Who moves a motor (toonface.providers/1 TOML): the idle face's blinks, breathing, gaze and "
                   "sway, and each layer's weight and fade [default: the life layer in silence: blink 17 a minute "
                   "as people do, breathe, look about, sway].")
@click.option("--seconds", default=None, type=FiniteFloat(min=0.1), help="Stop after this long.")
@click.option("--stream-to", default=None, metavar="HOST:PORT",
              help="Also send the motors shown as a motor stream (`toonface receive`, `toonface studio --receive`).")
@EYE_CONTACT
@LIFE
@NO_PHYSICS
def play(face: str, listen: str, udp: str | None, preview: str | None, output: str | None, loop_ms: float,
         size: str, track_path: str | None, once: bool, source_spec: str | None, camera: str | None,
         vmc: str | None, openseeface: str | None, vmc_out: str | None, providers_path: str | None,
         seconds: float | None, stream_to: str | None, eye_contact: bool, life: bool | None, no_physics: bool,
         background: str | None, virtual_camera: bool) -> None:
    """The live Animator: a face that moves as commanded over a socket, at a constant loop time.

    Commands, one per line, each answered "ok ..." or "error: ...":

    \b
      ELU 0 500 ERU 0 500     motors to targets (0..1) over milliseconds
      frame V1 .. V21 [MS]    all 21 motors, in ToonFace order
      play smile [MS]         a standard motion or expression (try: motions)
      hold MB 0.8             override a motor until `release MB` (or `release`)
      state                   the 21 values shown, and who moves each
                              (idle, tracking, motions or manual)

    Try `nc 127.0.0.1 7707` in another terminal, and --preview 127.0.0.1:8080 in a browser.
    Stop with Ctrl-C; recorded output is kept.
    """
    from player.live import ListenError, LiveSettings, run_live
    from player.providers import load_providers
    from toon import load_face, load_track
    from toonface.outputs import Outputs

    loop_time = loop_ms / 1000
    dims = parse_size(size)
    played = load_track(track_path) if track_path else None
    settings = LiveSettings(loop_time=loop_time, size=dims, tcp=_address(listen, "--listen", 7707),
                            udp=_address(udp, "--udp", 7708), preview=_address(preview, "--preview", 8080),
                            track=played, repeat=not once, seconds=seconds,
                            providers=load_providers(providers_path))
    face_obj = with_background(without_physics(load_face(face), no_physics), background)
    outputs = Outputs()
    if output is not None:
        settings.sinks.append(outputs.picture(output, rate=1 / loop_time, size=dims, live=True,
                                              background=face_obj.background))
    if virtual_camera:
        settings.sinks.append(outputs.picture("vcam:", rate=1 / loop_time, size=dims, background=face_obj.background))
    if stream_to is not None:
        host, port = _required_address(stream_to, "--stream-to", 7710)
        settings.shown.append(outputs.motor(f"udp://{host}:{port}", rate=1 / loop_time).write)
    if vmc_out is not None:
        settings.shown.append(outputs.motor(f"vmc://{vmc_out}", neutral=face_obj.neutral()).write)
    say = (lambda text: click.echo(text, err=True)) if output == "-" else click.echo
    follower = None
    if camera is not None:
        if source_spec is not None:
            raise click.BadParameter("give --camera or --source, not both", param_hint="--camera")
        source_spec = f"camera:{camera}"
    source_spec = bridge_spec(source_spec, vmc, openseeface, required=False)
    if eye_contact and source_spec is None:
        raise click.BadParameter("eye contact is for a performer: give --source, --camera, --vmc or --openseeface",
                                 param_hint="--eye-contact")
    if source_spec is not None:
        if track_path:
            raise click.BadParameter("give --motors or --source, not both", param_hint="--source")
        from toonface.send import Follower

        follower = Follower.open(source_spec, face_obj.neutral(), say, repeat=not once, eye_contact=eye_contact,
                                 life=life)
        settings.tracking = follower.latest.newest
        settings.extra = lambda t: follower.latest.extra() if follower is not None else {}
    settings.say = lambda text: click.echo(f"toonface: warning: {text}", err=True)

    def ready(addresses: dict[str, str]) -> None:
        for kind, where in addresses.items():
            say(f"{kind} {where}")
        say(f"playing {face_obj.name} at {1 / loop_time:g} loops a second (Ctrl-C stops)")
        (sys.stderr if output == "-" else sys.stdout).flush()

    try:
        with outputs:
            if follower is not None:
                follower.start()
            try:
                report = run_live(face_obj, settings, ready)
            finally:
                if follower is not None:
                    follower.stop()
        if follower is not None and follower.error is not None:
            raise follower.error
    except ListenError as exc:
        raise click.BadParameter(str(exc), param_hint={"tcp": "--listen", "udp": "--udp", "preview": "--preview"}[
            exc.kind]) from None
    say(f"stopped after {report.loops} loops; 95 % of loops started within "
        f"{report.lateness_p95_ms():.1f} ms of their time")
    if (dropped := report.summary(loop_time)) is not None:
        say(dropped)


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
def anim_knot(animation: str, output: str, motor: str, add: str | None, move: str | None, delete: int | None,
              ease: int | None, linear: int | None) -> None:
    """Insert, move or delete one knot of one motor, or ease the segment from it to the next or
    make it linear again (one of --add, --move, --delete, --ease, --linear). Knots are joined by
    straight lines unless eased, as CharToon's are."""

    if sum(x is not None for x in (add, move, delete, ease, linear)) != 1:
        raise click.UsageError("give one of --add, --move, --delete, --ease and --linear")
    codes = parse_codes(motor, "--motor", any_parameter=True)
    if not codes or len(codes) != 1:
        raise click.BadParameter(f"expected one motor code, got {motor!r}", param_hint="--motor")
    code = codes[0]
    source = af.load_animation(animation)
    try:
        if add is not None:
            out = an.insert_knot(source, code, *_pair(add, "--add"))
        elif move is not None:
            index, _, rest = move.partition(":")
            if not index.isdigit():
                raise click.BadParameter(f"expected INDEX:TIME,VALUE, got {move!r}", param_hint="--move")
            out = an.move_knot(source, code, int(index), *_pair(rest, "--move"))
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
    return time, value


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


PLAYER_COMMANDS = (play, anim)
