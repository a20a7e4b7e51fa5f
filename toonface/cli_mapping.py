"""The mapping subcommands: clean, calibrate, map, retarget, score."""

from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

import click
from click.core import ParameterSource

from toonface.cli_options import (
    BACKGROUND,
    FACE,
    LIFE,
    MIRROR,
    NO_PHYSICS,
    SIZE,
    FiniteFloat,
    TakeReading,
    parse_size,
    parse_span,
    parse_window,
    progress,
    read_take,
    take_options,
    with_background,
    without_physics,
)
from toonface.cli_trim import Trim, trim_options

if TYPE_CHECKING:
    from capture import Take
    from mapping import CleanSettings

_MAPPING = click.option("--mapping", default=None, metavar="NAME|FILE",
                        help="A mapping file or built-in preset (toon32, animface41, gluedots16, face) "
                             "[default: the preset whose marker set matches the take].")
_PROFILE = click.option("--profile", "profile_path", default=None, type=click.Path(dir_okay=False),
                        help="A performer profile (from `toonface calibrate`) [default: the marker set's built-in "
                             "typical profile with the rest from the take; where there is none, one calibrated on "
                             "the take].")
_NEUTRAL = click.option("--neutral", default=None, metavar="START:END|first|stillest",
                        help="Where the take is at rest: seconds, its first second with the head seen, or its "
                             "stillest second [default: a given profile's rest, else chosen and said: for a video, "
                             "the stillest stretch where nobody speaks; else the first second where it is about "
                             "as restful as any, else the second nearest the take's typical pose and stillest].")
_WORDS = ("first", "stillest")
_VOICE_FILL = click.option("--voice-fill/--no-voice-fill", default=True, show_default=True,
                           help="A video TAKE with sound: where the face's mouth is lost (turned away, covered, out "
                                "of the frame), the voice moves the mouth (the voice mapping, crossfaded over 0.1 s).")
_JSON = click.option("--json", "as_json", is_flag=True,
                     help="Print the take's report as one JSON object on standard output (the rest on standard "
                          "error) instead of as text on standard error.")
_CALIBRATE = click.option("--calibrate", "calibration", default=None, type=click.Path(dir_okay=False),
                          help="A calibration take of the same performer: its first second is the neutral and "
                               "all of it the range (instead of --profile).")


@dataclass(frozen=True)
class Cleaning:
    """The cleaning options of a command; :meth:`settings` checks them against a take."""

    spikes: bool
    max_gap_seconds: float
    cutoff_hz: float
    cutoff_given: bool  # on the command line (the default is capped below a slow take's limit instead)
    holds: bool = True

    def settings(self, rate: float) -> CleanSettings:
        """The settings for a take of ``rate`` Hz; a --cutoff it cannot hold is refused."""
        from mapping import CleanSettings

        if 0 < self.cutoff_hz < MIN_CUTOFF_HZ:  # 1e-300 Hz ended in "internal error: LinAlgError"
            raise click.BadParameter(f"{self.cutoff_hz:g} Hz: a low-pass cutoff is at least {MIN_CUTOFF_HZ:g} Hz "
                                     "(below that it flattens the face's motion); 0 means no smoothing",
                                     param_hint="--cutoff")
        if self.cutoff_given and self.cutoff_hz >= rate / 2:
            raise click.BadParameter(f"{self.cutoff_hz:g} Hz is not below half the take's {rate:g} Hz frame rate "
                                     f"(the fastest motion a {rate:g} Hz take holds is {rate / 2:g} Hz)",
                                     param_hint="--cutoff")
        return CleanSettings(self.spikes, self.max_gap_seconds, self.cutoff_hz, self.holds,
                             progress("filling gaps", "gap"))  # a bar on a terminal: an hour's take takes minutes


#: The lowest --cutoff taken (a blink or a word lasts a few tenths of a second).
MIN_CUTOFF_HZ = 0.1


def _clean_settings(fn):
    """--cutoff, --max-gap and --no-spikes, handed to the command as one :class:`Cleaning` named ``cleaning``."""
    from mapping import CleanSettings

    @functools.wraps(fn)
    def command(*args, no_spikes: bool, max_gap: float, cutoff: float, plain_smoothing: bool, **kwargs):
        given = click.get_current_context().get_parameter_source("cutoff") == ParameterSource.COMMANDLINE
        return fn(*args, cleaning=Cleaning(not no_spikes, max_gap, cutoff, given, not plain_smoothing), **kwargs)

    default = CleanSettings()
    command = click.option("--cutoff", default=default.cutoff_hz, show_default=True, type=FiniteFloat(min=0.0),
                           help="Zero-phase low-pass, Hz (0: no smoothing); below half the take's rate.")(command)
    command = click.option("--plain-smoothing", is_flag=True,
                           help="Smooth every frame by the --cutoff low-pass alike; by default a marker holding "
                                "still is smoothed more (judged against its own jitter), a moving one as --cutoff "
                                "says.")(command)
    command = click.option("--max-gap", default=default.max_gap_seconds, show_default=True,
                           type=FiniteFloat(min=0.0),
                           help="Fill gaps up to this many seconds (0: none); longer ones stay unseen.")(command)
    return click.option("--no-spikes", is_flag=True,
                        help="Keep spikes and label swaps (no robust spike rejection, no swap repair).")(command)


@click.command()
@click.argument("take", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False),
              help="Cleaned take (.npz .c3d .trc .csv).")
@_clean_settings
@click.option("--head-frame", is_flag=True,
              help="Write positions with head motion removed (the marker set's head frame); the head's yaw and "
                   "pitch go into the take's metadata (kept by .npz).")
@click.option("--markerset", default=None, metavar="NAME|FILE",
              help="The take's marker set [default: the built-in one its labels match].")
@_MAPPING
@take_options
def clean(take: str, output: str, head_frame: bool, markerset: str | None, mapping: str | None,
          cleaning: Cleaning, reading: TakeReading) -> None:
    """Clean a take offline: remove head motion, reject spikes, fill gaps, smooth without lag.

    Head motion is found by a robust rigid fit of the marker set's head references (the set is
    --markerset, the one --mapping reads, or recognised from the labels). Short gaps (up to 5
    frames) are bridged by a cubic spline, longer ones from the other markers' correlated motion;
    a marker missing longer than --max-gap stays unseen.
    """
    from capture import load_markerset, save_take
    from capture.takefile import dropped_channels
    from mapping import choose_mapping, clean_take

    if markerset and mapping:
        raise click.UsageError("give --markerset or --mapping, not both")
    loaded = read_take(take, reading, markerset, mapping)
    layout = load_markerset(markerset) if markerset else choose_mapping(loaded, mapping)[1] if mapping else None
    cleaned, report = clean_take(loaded, cleaning.settings(loaded.rate), layout, head_frame=head_frame)
    path = save_take(cleaned, output)
    click.echo(f"wrote {path}: {report.summary()}")
    if note := dropped_channels(cleaned, path):
        click.echo(note, err=True)


@click.command("calibrate")
@click.argument("take", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False), help="Profile to write (.toml).")
@_MAPPING
@click.option("--neutral", default=None, metavar="START:END|first|stillest",
              help="Where the take is at rest: seconds, its first second with the head seen, or its stillest "
                   "second [default: first].")
@click.option("--neutral-take", default=None, type=click.Path(dir_okay=False),
              help="Take the neutral from this take (its --neutral window, by default its first second) instead.")
@click.option("--range", "range_window", default=None, metavar="START:END",
              help="Seconds of the take that hold the range of motion (a calibration segment) [default: all].")
@click.option("--percentiles", default="0.5,99.5", show_default=True, metavar="LOW,HIGH",
              help="Percentiles of the range frames taken as each source's lowest and highest value.")
@click.option("--performer", default="", help="A name to keep in the profile.")
@click.option("--solve", is_flag=True,
              help="With --range (a sweep: each motor moved alone): also learn what each motor does to every marker, "
                   "kept in the profile, and solve all the motors it shows at once when mapping with it (off by "
                   "default: on the bench's synthetic performers it is as faithful as the rules on two and more "
                   "on two; see python -m bench fidelity).")
@_clean_settings
@take_options
def calibrate_cmd(take: str, output: str, mapping: str | None, neutral: str | None, neutral_take: str | None,
                  range_window: str | None, percentiles: str, performer: str, solve: bool, cleaning: Cleaning,
                  reading: TakeReading) -> None:
    """Make a performer profile (neutral pose and range of motion) from a take.

    The profile keeps every marker coordinate's rest value and range in the head frame, the
    head's rest pose, and any derived source (distance, difference, angle) the mapping reads;
    it is reused with every mapping and face of the same marker set.
    """
    from mapping import calibrate, choose_mapping, prepare, save_profile
    from mapping.take_notes import range_notes, still_warning, take_notes

    try:
        low, high = (float(p) for p in percentiles.split(","))
    except ValueError:
        low, high = 0.0, -1.0  # refused below
    if not 0 <= low < high <= 100:
        raise click.BadParameter(f"expected LOW,HIGH with 0 <= LOW < HIGH <= 100, got {percentiles!r}",
                                 param_hint="--percentiles")
    windows = parse_window(neutral or "first", words=_WORDS), parse_span(range_window, "--range")
    loaded = read_take(take, reading, mapping=mapping)
    settings = cleaning.settings(loaded.rate)
    chosen, markerset = choose_mapping(loaded, mapping)
    ranged = prepare(loaded, markerset, settings)
    rest = prepare(read_take(neutral_take, reading, mapping=mapping), markerset, settings) if neutral_take else ranged
    if solve and windows[1] is None:
        raise click.BadParameter("learns from a sweep: give its frames with --range START:END", param_hint="--solve")
    profile = calibrate(chosen, rest, windows[0], ranged, windows[1], (low, high), performer, solve=solve)
    path = save_profile(profile, output)
    if profile.solver is not None:
        click.echo(f"note: the solver learned {len(profile.solver.codes)} motors from {len(profile.solver.markers)} "
                   f"markers{profile.solver.left_out()}", err=True)
    if profile.head_axes is not None:
        click.echo(f"note: head angles are read about the head's own axes, {profile.notes['head_axes']}", err=True)
    for note in take_notes((rest, ranged), chosen):  # what map's report says of units, head fit, markers
        click.echo(note if note.startswith("warning:") else f"note: {note}", err=True)
    for note in range_notes(profile):
        click.echo(f"note: {note}", err=True)
    still = set(profile.notes.get("no_motion", "").split(", "))
    moving = sum(1 for key in profile.sources if key not in still)
    click.echo(f"wrote {path}: {len(profile.sources)} sources ({moving} moving), neutral {profile.notes['neutral']}, "
               f"range {profile.notes['range']}")
    if (warning := still_warning(profile, chosen)) is not None:
        click.echo(warning, err=True)


def _profile(profile_path: str | None, calibration: str | None, mapping: str | None, reading: TakeReading,
             read: dict[str, Take] | None = None):
    """The profile --profile names or --calibrate makes (None: neither); ``read`` holds takes
    already read by path, so that a take named twice is read once."""
    from mapping import calibrate, choose_mapping, load_profile, prepare
    if profile_path and calibration:
        raise click.BadParameter("give --profile or --calibrate, not both", param_hint="--calibrate")
    if profile_path:
        return load_profile(profile_path)
    if calibration:
        source = (read or {}).get(calibration) or read_take(calibration, reading, mapping=mapping)
        chosen, markerset = choose_mapping(source, mapping)
        return calibrate(chosen, prepare(source, markerset), "first")  # a calibration take starts at rest
    return None


@click.command("map")
@click.argument("take", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False), help="Motor track (.csv or .npz).")
@_MAPPING
@_PROFILE
@_CALIBRATE
@_NEUTRAL
@click.option("--face", default=None, metavar="NAME|FILE",
              help="Map the performer's neutral onto this face's rest pose.")
@MIRROR
@_clean_settings
@_VOICE_FILL
@LIFE
@_JSON
@trim_options
@take_options
def map_cmd(take: str, output: str, mapping: str | None, profile_path: str | None, calibration: str | None,
            neutral: str | None, face: str | None, mirror: bool, cleaning: Cleaning, voice_fill: bool,
            life: bool | None, as_json: bool, reading: TakeReading, trim: Trim) -> None:
    """Clean a take and map it onto the 21 motors (CSV: time + the motor codes, or .npz). TAKE
    may also be a talking-head video with no markers (its face tracked, as by retarget) or a
    voice (a sound file: .wav .mp3 .ogg ...).

    Ends with a report of what was chosen and how far to trust it: the units, the rest window
    and why, the profile, each motor's frames pinned at 0 or 1 and range used, and every warning.
    """
    from capture.sources import VIDEO_SUFFIXES
    from common.sound import has_audio
    from toon import load_face, save_track
    from toonface.pipeline import map_onto_face

    window = parse_window(neutral, words=_WORDS)
    loaded = read_take(take, reading, mapping=mapping)
    profile = _profile(profile_path, calibration, mapping, reading, {take: loaded})
    face_obj = load_face(face) if face else None
    track = map_onto_face(loaded, window, face_obj, mirror, mapping, profile, cleaning.settings(loaded.rate), life)
    if Path(take).suffix.lower() in VIDEO_SUFFIXES and voice_fill and has_audio(take):
        track = _fill_from_voice(track, loaded, take, face_obj, mapping, mirror, as_json)
    track = trim.track(track)
    click.echo(f"wrote {save_track(track, output)} ({track.frames} frames at {track.rate:g} Hz, "
               f"mapping {track.meta['mapping']}, {len(track.meta['mapped'])} motors mapped{trim.said()})", err=as_json)
    _report(track, Path(take).name, as_json)


def _fill_from_voice(track, loaded, video: str, face, mapping: str | None, mirror: bool, as_json: bool):
    """``track`` with its mouth from ``video``'s voice where the tracked face lost it (said aloud)."""
    from capture.voice_take import read_voice
    from mapping.voicefill import MOUTH, fill_from_voice, lost_mouth
    from mapping.workflow import choose_mapping
    from toonface.pipeline import map_onto_face

    chosen, markerset = choose_mapping(loaded, mapping)
    lost = lost_mouth(loaded, chosen, markerset)
    if not lost.any():
        return track
    voice = read_voice(video)
    filled, frames = fill_from_voice(track, lost, map_onto_face(voice, "first", face, mirror, life=False), voice.times)
    click.echo(f"note: the mouth ({', '.join(MOUTH)}) from the voice in {frames} frames where the face's mouth was "
               f"lost ({int(lost.any(axis=1).sum())} frames; --no-voice-fill keeps the face's own hold)", err=True)
    return filled


def _report(track, take: str, as_json: bool) -> None:
    """The take's report (:mod:`mapping.report`): as text on stderr, or as JSON on stdout."""
    import json

    from mapping.report import TakeReport

    report = TakeReport.from_dict({**track.meta["report"], "take": take})
    if as_json:
        click.echo(json.dumps(report.as_dict()))
    else:
        for line in report.lines():
            click.echo(line, err=True)


@click.command()
@click.argument("take", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(), help="A .mp4 file, or a folder for PNG frames.")
@FACE
@_MAPPING
@_PROFILE
@_CALIBRATE
@_NEUTRAL
@SIZE
@click.option("--fps", default=None, type=FiniteFloat(min=1.0, max=240.0),
              help="Output rate [default: the take's].")
@MIRROR
@click.option("--side-by-side", is_flag=True, help="A video TAKE: show it left of the cartoon, frame for frame.")
@BACKGROUND
@NO_PHYSICS
@_VOICE_FILL
@LIFE
@_JSON
@trim_options
@take_options
def retarget(take: str, output: str, face: str, mapping: str | None, profile_path: str | None,
             calibration: str | None, neutral: str | None, size: str, fps: float | None, mirror: bool,
             side_by_side: bool, background: str | None, no_physics: bool, voice_fill: bool, life: bool | None,
             as_json: bool, reading: TakeReading, trim: Trim) -> None:
    """Clean, map and render a take on a face, in one go. TAKE may also be a talking-head video
    with no markers: its face is tracked (MediaPipe) and its sound goes into the MP4; or a voice
    (a sound file: .wav .mp3 .ogg ...), whose mouth shapes move the mouth (the voice mapping)
    and which goes into the MP4."""
    from capture.sources import SOUND_SUFFIXES, VIDEO_SUFFIXES
    from common.sound import has_audio
    from player.beside import beside_width
    from toon import load_face
    from toonface.pipeline import map_onto_face, render, render_with_sound

    window, dims = parse_window(neutral, words=_WORDS), parse_size(size)
    face_obj = without_physics(with_background(load_face(face), background), no_physics)
    video = Path(take).suffix.lower() in VIDEO_SUFFIXES
    if side_by_side and not video:
        raise click.BadParameter("needs a video TAKE to show beside the cartoon", param_hint="--side-by-side")
    loaded = read_take(take, reading, mapping=mapping)
    profile = _profile(profile_path, calibration, mapping, reading, {take: loaded})
    track = map_onto_face(loaded, window, face_obj, mirror, mapping, profile, life=life)
    if video and voice_fill and has_audio(take):
        track = _fill_from_voice(track, loaded, take, face_obj, mapping, mirror, as_json)
    track = trim.track(track)
    bar = progress("render")(track.frames)
    voice = Path(take).suffix.lower() in SOUND_SUFFIXES
    fps = fps or (30.0 if voice else None)  # a voice's shapes come at 100 Hz: a movie need not
    from player.mux import SOUND_CONTAINERS

    sound = ((video and has_audio(take)) or voice) and (Path(output).suffix.lower() in SOUND_CONTAINERS)
    if video or voice:  # the performer's own voice goes with the cartoon
        frames = render_with_sound(track, face_obj, output, take, float(loaded.meta.get("start_time", 0.0))
                                   + trim.offset, dims, fps, progress=bar, side_by_side=side_by_side)
    else:
        frames = render(track, face_obj, output, dims, fps, progress=bar)
    width = dims[0] + (beside_width(take, dims[1]) if side_by_side else 0)
    heard = (video or voice) and has_audio(take)
    said = ", with its sound" if sound else ", no sound: the format carries none" if heard else (
        ", no sound in the video" if video else "")
    click.echo(f"wrote {output} ({frames} frames, {width}x{dims[1]}{said}{trim.said()})", err=as_json)
    _report(track, Path(take).name, as_json)


MAPPING_COMMANDS = (clean, calibrate_cmd, map_cmd, retarget)
