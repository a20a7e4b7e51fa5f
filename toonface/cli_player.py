"""The player subcommands: play (the live Animator)."""

from __future__ import annotations

import sys

import click

from player.animator import DEFAULT_LOOP_TIME
from player.live import LiveSettings, run_live
from player.server import parse_address
from player.sinks import open_sink
from toon import load_face, load_track
from toonface.cli_options import FACE, SIZE, parse_size


def _address(value: str | None, option: str, port: int) -> tuple[str, int] | None:
    if value is None or value.lower() == "off":
        return None
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
              help="Also record: a .mp4 file, a folder for PNG frames, or - for raw RGB on standard output.")
@click.option("--loop-ms", default=DEFAULT_LOOP_TIME * 1000, show_default=True, type=click.FloatRange(5, 1000),
              help="Loop time: one frame and one slice per moving motor per loop (ToonFace used 100).")
@SIZE
@click.option("--track", "track_path", default=None, type=click.Path(dir_okay=False),
              help="Play a motor track (.csv movie script or .npz) at its own rate instead of commands.")
@click.option("--once", is_flag=True, help="With --track: play it once and stop (default: loop).")
@click.option("--seconds", default=None, type=click.FloatRange(min=0.1), help="Stop after this long.")
def play(face: str, listen: str, udp: str | None, preview: str | None, output: str | None, loop_ms: float,
         size: str, track_path: str | None, once: bool, seconds: float | None) -> None:
    """The live Animator: a face that moves as commanded over a socket, at a constant loop time.

    Commands, one per line, each answered "ok ..." or "error: ...":

    \b
      ELU 0 500 ERU 0 500     motors to targets (0..1) over milliseconds
      frame V1 .. V21 [MS]    all 21 motors, in ToonFace order
      play smile [MS]         a standard motion or expression (try: motions)
      state                   the 21 current values

    Try `nc 127.0.0.1 7707` in another terminal, and --preview 127.0.0.1:8080 in a browser.
    Stop with Ctrl-C; recorded output is kept.
    """
    loop_time = loop_ms / 1000
    dims = parse_size(size)
    settings = LiveSettings(loop_time=loop_time, size=dims, tcp=_address(listen, "--listen", 7707),
                            udp=_address(udp, "--udp", 7708), preview=_address(preview, "--preview", 8080),
                            track=load_track(track_path) if track_path else None, repeat=not once, seconds=seconds)
    face_obj = load_face(face)
    if output is not None:
        settings.sinks.append(open_sink(output, 1 / loop_time, dims))
    say = (lambda text: click.echo(text, err=True)) if output == "-" else click.echo

    def ready(addresses: dict[str, str]) -> None:
        for kind, where in addresses.items():
            say(f"{kind} {where}")
        say(f"playing {face_obj.name} at {1 / loop_time:g} loops a second (Ctrl-C stops)")
        (sys.stderr if output == "-" else sys.stdout).flush()

    report = run_live(face_obj, settings, ready)
    say(f"stopped after {report.loops} loops; 95 % of loops started within "
        f"{report.lateness_p95_ms():.1f} ms of their time")


PLAYER_COMMANDS = (play,)
