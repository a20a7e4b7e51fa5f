"""``toonface render``, ``export`` and ``score``: a motor track drawn into the pictures and pages
other tools take (videos with alpha, SVG and Lottie, a web page that plays by itself), and as
staves."""

from __future__ import annotations

import click

from toonface.cli_options import (
    BACKGROUND,
    FACE,
    NO_PHYSICS,
    SIZE,
    FiniteFloat,
    parse_codes,
    parse_size,
    progress,
    with_background,
    without_physics,
)
from toonface.cli_trim import Trim, trim_options


@click.command("render")
@click.argument("motors", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(),
              help="A .mp4 file (H.264); with alpha, .webm (VP9), .mov (ProRes 4444), .apng or .webp; an animated "
                   ".svg; a Lottie .json; a folder for PNG (or --format svg) frames; or - for raw RGB frames on "
                   "standard output.")
@FACE
@SIZE
@click.option("--fps", default=None, type=FiniteFloat(min=1.0, max=240.0),
              help="Output rate [default: the track's].")
@BACKGROUND
@NO_PHYSICS
@click.option("--format", "fmt", default=None, type=click.Choice(("png", "svg", "lottie")),
              help="A folder OUTPUT: PNG frames (the default) or SVG frames, one file per frame; lottie: a .json "
                   "OUTPUT is a Lottie animation (what a .json OUTPUT is anyway).")
@click.option("--sound", default=None, type=click.Path(dir_okay=False),
              help="A voice (a sound file, or a video's sound) muxed in from its start (from --start with it): "
                   "an .mp4, .mov or .webm OUTPUT only.")
@trim_options
def render_cmd(motors: str, output: str, face: str, size: str, fps: float | None, background: str | None,
               no_physics: bool, fmt: str | None, sound: str | None, trim: Trim) -> None:
    """Draw a motor track (.csv movie script or .npz) or a knot-point animation (.toml) on a face.

    With --background none (or a face whose background is transparent) the picture keeps its
    alpha: composite it over anything in an editor, a compositor or a web page. An .svg OUTPUT
    is one animated SVG of the whole track that browsers play with no script (SMIL), keyed only
    where an outline strays more than a pixel (at 500 pixels) from its interpolation; a .json
    OUTPUT is a Lottie animation (Bodymovin JSON: shape layers with keyframed paths, layer masks
    for the holes) for Lottie players, After Effects and mobile apps.

    With --sound, the voice a track was lip-synced from (or any sound) plays with it: the
    picture's packets are written as drawn and the sound is encoded for the picture's length."""
    from pathlib import Path

    from toon import load_face, load_track
    from toon.animation_file import load_animation
    from toonface.pipeline import render, render_with_sound

    dims = parse_size(size)
    if sound is not None:
        from player.mux import SOUND_CONTAINERS, has_audio

        if Path(output).suffix.lower() not in SOUND_CONTAINERS:
            kinds = list(SOUND_CONTAINERS)
            raise click.BadParameter(f"{output} carries no sound: give an {', '.join(kinds[:-1])} or {kinds[-1]} "
                                     "output", param_hint="--sound")
        if not Path(sound).is_file():
            raise click.BadParameter(f"{sound}: no such file", param_hint="--sound")
        if not has_audio(sound):
            raise click.BadParameter(f"{sound}: no sound in it", param_hint="--sound")
    face_obj = without_physics(with_background(load_face(face), background), no_physics)
    if motors.lower().endswith(".toml"):  # a knot-point animation: sampled at the output rate
        track = load_animation(motors).sample(fps or 30.0, face_obj.neutral())
    else:
        track = load_track(motors)
    track = trim.track(track)
    bar = progress("render")(track.frames)
    if sound is not None:
        frames = render_with_sound(track, face_obj, output, sound, trim.offset, dims, fps, progress=bar)
    else:
        frames = render(track, face_obj, output, dims, fps, progress=bar, fmt=fmt)
    said = f", with the sound of {Path(sound).name}" if sound else ""
    click.echo(f"wrote {output} ({frames} frames, {dims[0]}x{dims[1]}{said}{trim.said()})", err=output == "-")


@click.group()
def export() -> None:
    """Results for other tools: a web page that plays a track with no server."""


@export.command("web")
@click.argument("motors", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False), help="The page (.html).")
@FACE
@SIZE
@click.option("--fps", default=30.0, show_default=True, type=FiniteFloat(min=1.0, max=120.0),
              help="Frames a second a knot-point animation (.toml) is sampled at; a track's own samples "
                   "travel as they are, and the page draws at the screen's rate between them.")
@click.option("--sound", default=None, type=click.Path(dir_okay=False),
              help="A sound file (or a video's sound) to embed and play with the face.")
@click.option("--transparent", is_flag=True,
              help="No background and no controls: the face alone, looping (OBS's browser source).")
@click.option("--paused", is_flag=True, help="Open paused at the start.")
@NO_PHYSICS
@trim_options
def export_web_cmd(motors: str, output: str, face: str, size: str, fps: float, sound: str | None, transparent: bool,
                   paused: bool, no_physics: bool, trim: Trim) -> None:
    """MOTORS (.csv/.npz, or a knot-point animation .toml) on a face as one self-contained HTML
    file: it plays in any browser with no server, with play/pause and a time slider, and the
    sound in step where one is given. The page draws the face itself, the studio's own drawing,
    from the face's web rig and the track's samples, its physics included."""
    from pathlib import Path

    from toon import load_face, load_track
    from toon.animation_file import load_animation
    from toonface.web_export import export_web

    if Path(output).suffix.lower() not in (".html", ".htm"):
        raise click.BadParameter(f"{output}: expected a .html page", param_hint="--output")
    face_obj = without_physics(load_face(face), no_physics)
    track = trim.track(load_animation(motors).sample(fps, face_obj.neutral()) if motors.lower().endswith(".toml")
                       else load_track(motors))
    path = export_web(track, face_obj, output, size=parse_size(size), sound=sound, transparent=transparent,
                      paused=paused, title=f"{Path(motors).stem} on {face_obj.name}",
                      sound_span=(trim.offset, trim.offset + track.duration) if trim.given else None)
    click.echo(f"wrote {path} ({path.stat().st_size // 1024} KB, {track.duration:.2f} s"
               f"{', with sound' if sound else ''}{', transparent' if transparent else ''}{trim.said()})")


@click.command()
@click.argument("motors", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False),
              help="The staves as a picture (.png .jpg .webp .bmp .tif) or as text (.txt).")
@click.option("--compare", default=None, type=click.Path(dir_okay=False),
              help="A second track drawn over the first in another colour (before/after a filter, truth/mapped).")
@click.option("--motors", "codes", default=None, metavar="CODE,CODE,...", help="Staves to draw [default: all 21].")
@click.option("--width", default=1200, show_default=True, type=click.IntRange(200, 8000), help="Image width, pixels.")
@click.option("--text", is_flag=True, help="Also print the staves as text (block characters), one line per motor.")
@click.option("--sound", "sound_path", default=None, type=click.Path(dir_okay=False, exists=True),
              help="Draw this file's loudness as a last stave (the video the track was mapped from: check the "
                   "mouth against the voice).")
def score(motors: str, output: str, compare: str | None, codes: str | None, width: int, text: bool,
          sound_path: str | None) -> None:
    """Draw motor curves as staves, one per motor, like CharToon's Animation Editor.

    Each stave spans 0..1 with the motor's code at the left and a time axis below; with
    --compare, the second track is drawn over the first (the first in dark blue, the second
    in orange) and each stave's RMS difference is printed at its right.
    """
    from common import atomic_path
    from player.score import save_score, score_text
    from player.sheet import check_image_suffix
    from toon import load_track

    as_text = output.lower().endswith(".txt")
    if not as_text:
        check_image_suffix(output)
    track = load_track(motors)
    picked = parse_codes(codes, also=track.extra_codes)  # the 21, then the track's parameters (HT...)
    other = load_track(compare) if compare else None
    sound = None
    if sound_path:
        from common.sound import sound_envelope

        sound = sound_envelope(sound_path)
    if as_text:
        with atomic_path(output) as tmp:
            tmp.write_text("\n".join(score_text(track, picked)) + "\n", encoding="utf-8")
    else:
        save_score(track, output, other, picked, width, sound)
    if text:
        for line in score_text(track, picked):
            click.echo(line)
    click.echo(f"wrote {output} ({track.frames} frames, {len(picked) if picked else 21} staves)")


OUTPUT_COMMANDS = (render_cmd, export, score)
