"""``toonface lipsync``: a voice's mouth shapes, as the cues lip-sync tools read."""

from __future__ import annotations

from pathlib import Path

import click

from toonface.cli_options import LISTEN, FiniteFloat
from toonface.cli_trim import Trim, trim_options

#: What ``lipsync -o`` writes, by suffix.
CUE_FORMATS = {".tsv": "Rhubarb's TSV", ".json": "Rhubarb's JSON", ".xml": "Rhubarb's XML",
               ".dat": "Moho's and OpenToonz's switch data"}


@click.command()
@click.argument("voice", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False),
              help="Mouth cues: .tsv (Rhubarb's: start<TAB>shape, the last line the end at rest), .json or .xml "
                   "(Rhubarb's: metadata and mouthCues with start, end and shape), or .dat (Moho's and OpenToonz's "
                   "switch data: FRAME SHAPE lines at --fps).")
@click.option("--fps", "--dat-fps", "fps", default=24.0, show_default=True, type=FiniteFloat(min=1, max=240),
              help="The frame rate the cues are for: each starts on a frame and holds two at least (a closed mouth "
                   "for b, p and m one at least), so that no shape flickers; a .dat counts its frames at it.")
@click.option("--every-frame", is_flag=True,
              help="The cues as heard, a shape for each 10 ms whatever the frame rate (they read back as the "
                   "voice's own motors exactly; an animation at 24 or 30 fps would flicker).")
@click.option("--text", default=None, metavar="WORDS|@FILE",
              help="The words spoken (or @FILE holding them): aligned with the sound, which places each phone, "
                   "and opened as --listen words opens them [default: no words needed, see --listen].")
@LISTEN
@trim_options
def lipsync(voice: str, output: str, fps: float, every_frame: bool, text: str | None, listen: str | None,
            trim: Trim) -> None:
    """Mouth shapes from a voice: a sound file (WAV, MP3, OGG, anything FFmpeg decodes) or the
    sound of a video, heard offline in any language (or, with --listen words, the English words
    recognised in it; with --text, the English words given, aligned),
    as Rhubarb Lip Sync's mouth cues (shapes A-H and X) for Moho, OpenToonz, Blender, Spine and
    the like. The cues read back as a take: `toonface map cues.tsv` gives the motors
    `toonface map VOICE` gives from the phones or the words, and from the sound alone (which
    weighs a frame between two shapes) the same a shape at a time.

    Silence is rest (X) whatever was heard in it, and the blend between shapes reaches 50 ms
    either side. Each cue holds two frames at least at --fps (a closed mouth one), as an
    editor's timeline needs. From words or phones, a vowel's shape comes a little early, no shape is held for less
    than 30 ms, and a pause under 0.2 s keeps the shape before it.
    """
    from capture.cues import cues_text, held_cues
    from capture.voice import FRAME_RATE, mouth_cues
    from capture.voice import heard as said
    from capture.voice_take import hear_voice
    from common import atomic_path
    from toon.track import kept_rows
    from toonface.cli_options import read_words

    suffix = Path(output).suffix.lower()
    if suffix not in CUE_FORMATS:
        raise click.BadParameter(f"{output}: expected {' or '.join(CUE_FORMATS)} ({', '.join(CUE_FORMATS.values())})",
                                 param_hint="--output")
    words = read_words(text) if text is not None else None
    heard = hear_voice(voice, words, listen or "sound")
    shapes = heard.shapes  # heard whole (its words, pauses and level), then cut: the cues start at 0 at --start
    if trim.given:  # (the rule MotorTrack.part cuts tracks by)
        shapes = shapes[kept_rows(len(shapes), FRAME_RATE, trim.start, trim.end, Path(voice).name)]
    cues = mouth_cues(shapes)
    if not every_frame:
        cues = held_cues(cues, fps)
    duration = len(shapes) / FRAME_RATE
    for note in heard.notes:
        click.echo(f"note: {note}", err=True)
    with atomic_path(output) as tmp:
        tmp.write_text(cues_text(cues, suffix, voice, words, fps), encoding="utf-8")
    shaped = sum(1 for _, _, shape in cues if shape != "X")
    click.echo(f"wrote {output}: {len(cues)} mouth cues over {duration:.2f} s ({shaped} speaking), "
               + ("the words given aligned, opened as the sound and their phones say" if words else
                  f"from the {len(said(heard.phones)[0])} words heard (English)" if listen == "words" else
                  "from the phones heard (no words given)" if listen == "phones" else
                  "from the sound's spectrum (no words given)") + trim.said())


VOICE_COMMANDS = (lipsync,)
