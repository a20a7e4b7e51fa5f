"""``toonface play``: the live Animator (knot-point animations are :mod:`toonface.cli_anim`)."""

from __future__ import annotations

import sys

import click

from mapping.settings import HOLD_SECONDS, MAX_GAP_SECONDS
from player.animator import DEFAULT_LOOP_TIME
from toonface.cli_options import (
    BACKGROUND,
    EYE_CONTACT,
    FACE,
    LIFE,
    LIVE_HOLD_GAP,
    LIVE_MAX_GAP,
    NO_PHYSICS,
    OPENSEEFACE,
    SIZE,
    VIRTUAL_CAMERA,
    VMC,
    VMC_OUT,
    FiniteFloat,
    bridge_spec,
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
@LIVE_MAX_GAP
@LIVE_HOLD_GAP
@LIFE
@NO_PHYSICS
def play(face: str, listen: str, udp: str | None, preview: str | None, output: str | None, loop_ms: float,
         size: str, track_path: str | None, once: bool, source_spec: str | None, camera: str | None,
         vmc: str | None, openseeface: str | None, vmc_out: str | None, providers_path: str | None,
         seconds: float | None, stream_to: str | None, eye_contact: bool, max_gap: float, hold_gap: float,
         life: bool | None, no_physics: bool, background: str | None, virtual_camera: bool) -> None:
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
    if source_spec is None and (max_gap, hold_gap) != (MAX_GAP_SECONDS, HOLD_SECONDS):
        hint = "--max-gap" if max_gap != MAX_GAP_SECONDS else "--hold-gap"
        raise click.BadParameter("filling lost markers is for a performer: give --source, --camera, --vmc or "
                                 "--openseeface", param_hint=hint)
    if source_spec is not None:
        if track_path:
            raise click.BadParameter("give --motors or --source, not both", param_hint="--source")
        from toonface.send import Follower

        follower = Follower.open(source_spec, face_obj.neutral(), say, repeat=not once, eye_contact=eye_contact,
                                 life=life, regress_seconds=max_gap, hold_seconds=hold_gap)
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


PLAYER_COMMANDS = (play,)
