"""The ``toonface`` command. Arguments are parsed in :func:`main`, never at import.

Every subcommand exits 0 on success and non-zero with a one-line ``toonface: error: ...``
message (no traceback) on bad input; set ``TOONFACE_DEBUG=1`` to see tracebacks.
"""

from __future__ import annotations

import json
import logging
import os
import signal
import sys
import threading
import warnings
from dataclasses import replace

import click

from capture.colours import HUES
from common.errors import Interrupted, Terminated, ToonfaceError
from common.memory import keep_freed_memory
from toonface.cli_anim import ANIM_COMMANDS
from toonface.cli_batch import BATCH_COMMANDS
from toonface.cli_layout import LAYOUT_COMMANDS
from toonface.cli_mapping import MAPPING_COMMANDS
from toonface.cli_options import (
    FACE,
    FiniteFloat,
    TakeReading,
    parse_size,
    progress,
    read_take,
    take_options,
)
from toonface.cli_output import OUTPUT_COMMANDS
from toonface.cli_player import PLAYER_COMMANDS
from toonface.cli_room import ROOM_COMMANDS
from toonface.cli_stream import STREAM_COMMANDS
from toonface.cli_studio import STUDIO_COMMANDS
from toonface.cli_voice import VOICE_COMMANDS

# Commands import the stages they use when they run: `toonface --help` loads none of them.

@click.group(context_settings={"help_option_names": ["-h", "--help"], "max_content_width": 100})
@click.version_option(package_name="toonface")
@click.option("-v", "--verbose", is_flag=True, help="Log diagnostics to stderr.")
def cli(verbose: bool) -> None:
    """Turn a performer's face into a cartoon face.

    Marker takes are cleaned, calibrated and mapped onto the 21 motors of a ToonFace face, then
    drawn offscreen with OpenGL into a video or frames. Start with `toonface demo`.
    """
    logging.basicConfig(level=logging.INFO if verbose else logging.WARNING, format="toonface: %(message)s")


@cli.command()
@click.option("--out", "out_dir", default="toonface-demo", show_default=True, type=click.Path(file_okay=False),
              help="Folder for demo.mp4, take.npz, motors.csv and truth.csv.")
@click.option("--seconds", default=10.0, show_default=True, type=FiniteFloat(min=1.0, max=600.0))
@click.option("--rate", default=30.0, show_default=True, type=FiniteFloat(min=1.0, max=240.0),
              help="Frames per second.")
@click.option("--size", default=512, show_default=True, type=click.IntRange(16, 4096), help="Square frame size, even.")
@FACE
@click.option("--seed", default=0, show_default=True, type=int)
def demo(out_dir: str, seconds: float, rate: float, size: int, face: str, seed: int) -> None:
    """The whole pipeline on built-in data: a synthetic performer, mapped and rendered to MP4."""
    from toonface.pipeline import run_demo

    if size % 2:
        raise click.BadParameter(f"H.264 needs an even size, got {size}", param_hint="--size")
    result = run_demo(out_dir, seconds=seconds, rate=rate, size=size, face=face, seed=seed,
                      progress_factory=progress("render"))
    for label, path in (("video", result.video), ("take", result.take), ("motors", result.motors),
                        ("truth", result.truth)):
        click.echo(f"wrote {label:<7}{path}")
    click.echo(f"{result.frames} frames at {size}x{size}; mapped motors differ from the truth by "
               f"{result.mean_abs_error:.4f} on average (0-1 scale)")
    for stage, secs in result.times.seconds.items():
        click.echo(f"  {stage:<22}{secs:7.2f} s")
    click.echo(f"  {'total':<22}{sum(result.times.seconds.values()):7.2f} s")


@cli.command()
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False), help="Take file to write (.npz).")
@click.option("--seconds", default=10.0, show_default=True, type=FiniteFloat(min=0.1, max=3600.0))
@click.option("--rate", default=30.0, show_default=True, type=FiniteFloat(min=1.0, max=1000.0))
@click.option("--noise", default=0.2, show_default=True, type=FiniteFloat(min=0.0), help="Jitter, mm (σ).")
@click.option("--seed", default=0, show_default=True, type=int)
@click.option("--gaps", default=0.0, show_default=True, type=FiniteFloat(min=0.0),
              help="Occlusions per marker per second.")
@click.option("--gap-seconds", default=0.3, show_default=True, type=FiniteFloat(min=0.0), help="Occlusion length.")
@click.option("--spikes", default=0.0, show_default=True, type=FiniteFloat(0.0, 1.0),
              help="Share of marker-samples with a one-frame 15 mm spike.")
@click.option("--swaps", default=0.0, show_default=True, type=FiniteFloat(0.0, 1.0),
              help="Chance per frame that two neighbouring markers swap labels for 10 frames.")
@click.option("--drift", default=0.0, show_default=True, type=FiniteFloat(min=0.0), help="Slow drift, mm.")
@click.option("--expressions", metavar="NAME,NAME,...",
              help="Repertoire expressions to act in turn "
                   "[default: happiness,surprise,sadness,anger,fear,disgust,wink].")
@click.option("--calibration", is_flag=True,
              help="Start with a calibration segment: 1 s neutral, then each motor group to its extremes (14.4 s).")
@click.option("--max-turn", default=30.0, show_default=True, type=FiniteFloat(0.0, 30.0),
              help="Largest head turn, degrees.")
@click.option("--script", "script_file", type=click.Path(dir_okay=False),
              help="A performance script (TOML, toonface.performance/1) instead of the generated one; "
                   "it sets its own length.")
def synth(output: str, seconds: float, rate: float, noise: float, seed: int, gaps: float, gap_seconds: float,
          spikes: float, swaps: float, drift: float, expressions: str | None, calibration: bool, max_turn: float,
          script_file: str | None) -> None:
    """A synthetic performer with the toon32 markers; also writes the true motors beside it.

    The performance is generated (a neutral first second, then expressions, talking, blinks,
    gaze shifts and head turns) or read from --script. --seed moves the jitter and the faults,
    not the performance. Faults (each off by default) imitate real capture: occlusion gaps,
    spikes, label swaps and drift, on top of the --noise jitter.
    """
    from capture import save_take, synthesize
    from capture.faults import Faults, apply_faults
    from capture.performance import default_performance, load_performance
    from toon import load_expressions, save_track
    from toonface.pipeline import truth_track

    repertoire = load_expressions()  # validated once here, then handed to the performer
    poses = {name: dict(expression.motors) for name, expression in repertoire.items()}
    if script_file is not None:
        performance = load_performance(script_file)
    else:
        names = None if expressions is None else tuple(n.strip() for n in expressions.split(",") if n.strip())
        unknown = [n for n in names or () if n not in repertoire]
        if unknown:
            raise click.BadParameter(f"not in the repertoire: {', '.join(unknown)} "
                                     f"(known: {', '.join(repertoire)})", param_hint="--expressions")
        performance = default_performance(seconds, names, calibration=calibration, max_turn_deg=max_turn)
    synthetic = synthesize(rate=rate, noise_mm=noise, seed=seed, performance=performance, poses=poses)
    take = synthetic.take
    faults = Faults(gap_rate=gaps, gap_seconds=gap_seconds, spike_rate=spikes, swap_rate=swaps, drift_mm=drift)
    if faults.active():
        take, _ = apply_faults(take, faults, seed=seed)
    path = save_take(take, output)
    truth = save_track(truth_track(synthetic), path.with_name(f"{path.stem}.truth.csv"))
    click.echo(f"wrote {path} ({take.frames} frames, {take.markers} markers, {int((~take.valid).sum())} missing "
               f"samples) and {truth}")


def _plot(loaded, plot_path: str, motion: bool, layout: str | None, mapping_name: str | None) -> None:
    """``info --plot``: the take in its own axes, or in a marker set's head frame with the roles a
    mapping gives its markers."""
    from capture.markerset import find_markerset, load_markerset
    from capture.plot import in_head_frame, plot_take

    roles: dict[str, list[str]] = {}
    if mapping_name is not None:
        from mapping.mapfile import load_mapping

        mapping = load_mapping(mapping_name)
        layout = layout or mapping.markerset
        for rule in mapping.rules:
            for source in rule.sources:
                for marker in source.markers:
                    roles.setdefault(marker, []).append(rule.code)
    known = load_markerset(layout) if layout else find_markerset(loaded.labels)
    if layout and known is not None:
        loaded = in_head_frame(loaded, known)
    found = known.match(loaded.labels) if known else {}
    words = {found.get(marker, marker): " ".join(dict.fromkeys(codes)) for marker, codes in roles.items()}
    plot_take(loaded, plot_path, motion, tuple(found.get(r, r) for r in known.head_reference) if known else (),
              words, known.name if layout and known else None)


@cli.command()
@click.argument("take", type=click.Path(dir_okay=False))
@click.option("--json", "as_json", is_flag=True, help="One JSON object instead of text.")
@click.option("--plot", "plot_path", default=None, type=click.Path(dir_okay=False),
              help="Draw the markers' neutral from the front, side and top, labelled (PNG), to tell them apart.")
@click.option("--plot-motion", is_flag=True, help="With --plot: also each marker's path over the take.")
@click.option("--markerset", "layout", default=None, metavar="NAME|FILE",
              help="The take's marker set: a table is read with its [tables] rate and units, and --plot draws the "
                   "take in its head frame (front, side and top of the face), its head references ringed "
                   "[default: the take's own axes].")
@click.option("--mapping", "mapping_name", default=None, metavar="NAME|FILE",
              help="As --markerset, with the mapping's marker set; --plot also labels each marker with the motors "
                   "this mapping drives from it.")
@take_options
def info(take: str, as_json: bool, plot_path: str | None, plot_motion: bool, layout: str | None,
         mapping_name: str | None, reading: TakeReading) -> None:
    """Frames, markers, rate, duration, units and gaps of a take (.c3d .trc .csv .npz).

    With --json, prints one object with the keys frames, markers, rate, duration, units, dims,
    labels, missing (total missing marker-samples), missing_per_marker, longest_gap, source and
    channels (each blendshape score of a markerless take: its range and frames measured).
    """
    from capture.info import describe, summarize

    if plot_motion and not plot_path:
        raise click.UsageError("--plot-motion draws into the --plot picture: give --plot too")
    loaded = read_take(take, reading, layout, mapping_name)
    summary = summarize(loaded)
    if plot_path:
        _plot(loaded, plot_path, plot_motion, layout, mapping_name)
        click.echo(f"wrote {plot_path}", err=as_json)
    if as_json:
        click.echo(json.dumps(summary))
    else:
        click.echo(f"{take}")
        for line in describe(summary):
            click.echo(f"  {line}" if line else "")


@cli.command()
@click.argument("video", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False),
              help="Take file to write (.npz or .csv: the take is planar).")
@click.option("--markers", "method", type=click.Choice(["dots", "aruco", "face"]), default="dots", show_default=True,
              help="Coloured dots identified by a marker set's layout, ArUco markers identified by id, or face: no "
                   "markers, a face's landmarks (MediaPipe; the marker set face, in 3-D).")
@click.option("--markerset", default="toon32", show_default=True, metavar="NAME|FILE",
              help="Dots: the layout whose neutral pose identifies them (pupils excluded).")
@click.option("--colour", default="blue", show_default=True, type=click.Choice(sorted(HUES)),
              help="Dots: their colour.")
@click.option("--init", "start_frame", default=0, show_default=True, type=click.IntRange(min=0),
              help="Dots: a frame where the face is neutral and every dot shows; earlier frames are NaN.")
@click.option("--names", "names_file", type=click.Path(dir_okay=False),
              help='ArUco: TOML [names] table, id = "marker name" [default: aruco_<id>].')
@click.option("--corners", is_flag=True, help="ArUco: four corner points per marker instead of its centre.")
@click.option("--dictionary", default="aruco_original", show_default=True,
              help="ArUco: OpenCV's predefined dictionary.")
@click.option("--mm-per-pixel", type=FiniteFloat(min=0, min_open=True), help="ArUco: image scale.")
@click.option("--marker-mm", type=FiniteFloat(min=0, min_open=True),
              help="ArUco: printed side length, to measure the scale (with --corners).")
def track(video: str, output: str, method: str, markerset: str, colour: str, start_frame: int,
          names_file: str | None, corners: bool, dictionary: str, mm_per_pixel: float | None,
          marker_mm: float | None) -> None:
    """Track markers in a video (anything OpenCV or PyAV decodes) into a take: planar for dots and
    ArUco, 3-D camera-space millimetres for a face without markers."""
    from capture import save_take
    from capture.takefile import dropped_channels
    from capture.video_tracking import load_aruco_names, track_video

    names = load_aruco_names(names_file) if names_file else None
    take = track_video(video, method, markerset, colour, start_frame, names, corners, dictionary, mm_per_pixel,
                       marker_mm, progress_factory=progress("track"))
    path = save_take(take, output)
    seen = take.valid.any(axis=0).sum()
    scale = f", {take.meta['mm_per_pixel']:.4g} mm per pixel" if "mm_per_pixel" in take.meta else ""
    faces = f", a face in {take.meta['faces_found']} frames" if "faces_found" in take.meta else ""
    click.echo(f"wrote {path} ({take.frames} frames, {seen} of {take.markers} markers seen, "
               f"{int((~take.valid).sum())} missing samples{scale}{faces})")
    if note := dropped_channels(take, path):
        click.echo(note, err=True)


@cli.command()
def faces() -> None:
    """List the built-in faces."""
    from toon import builtin_faces, load_face

    for name in builtin_faces():
        click.echo(f"{name:<12}{load_face(name).description}")


@cli.command()
@click.argument("name")
@click.option("--sheet", "sheet_path", type=click.Path(dir_okay=False),
              help="Write a contact sheet of every expression on the face, labelled (.png .jpg .webp ...).")
@click.option("--svg", "svg_path", type=click.Path(dir_okay=False),
              help="Write one expression of the face as SVG (no OpenGL needed).")
@click.option("--expression", default="neutral", show_default=True, help="The expression --svg draws.")
@click.option("--expressions", "repertoire", default="expressions", show_default=True,
              help="Expression repertoire: built-in name or TOML file.")
@click.option("--size", default="256", show_default=True, help="Pixels per face picture, N or WxH.")
@click.option("--save", "save_path", type=click.Path(dir_okay=False),
              help="Write the face as a face file (.json) to start your own from: edit it, or open it in the studio.")
@click.option("--name", "new_name", default=None,
              help="With --save: the saved face's name (titles, reports) [default: the file's name, 'mine' for "
                   "mine.json].")
def face(name: str, sheet_path: str | None, svg_path: str | None, expression: str, repertoire: str,
         size: str, save_path: str | None, new_name: str | None) -> None:
    """Check a face (built-in NAME or a JSON file) and draw it.

    Without options, validates the face and prints a summary. With --sheet, renders every
    expression of the repertoire (neutral, the six basic ones, blink, wink) into one labelled PNG,
    and then each of the face's parameters beyond the 21 (HT, UL...) at its extremes. With --save,
    writes it as a face file of your own (a built-in face's component libraries stay built-in).
    """
    from player.sheet import check_image_suffix, expression_sheet, save_image
    from toon import FaceRig, load_expressions, load_face, save_face, save_svg

    if new_name is not None and not save_path:
        raise click.BadParameter("names the face --save writes: give --save too", param_hint="--name")
    if sheet_path:
        check_image_suffix(sheet_path)
    loaded = load_face(name)
    rig = FaceRig(loaded)  # binds skeletons and features: reports a bad face even without output
    expressions = load_expressions(repertoire)
    cell = parse_size(size)
    if expression not in expressions:
        raise click.BadParameter(f"unknown expression {expression!r} (one of {', '.join(expressions)})",
                                 param_hint="--expression")
    if sheet_path:
        save_image(expression_sheet(rig, expressions, cell=cell), sheet_path)
        extremes = f" and {len(loaded.extra_codes)} parameters at their extremes" if loaded.extra_codes else ""
        click.echo(f"wrote {sheet_path} ({len(expressions)} expressions{extremes} on {loaded.name})")
    if svg_path:
        shown = expressions[expression]
        save_svg(rig.geometry(shown.pose(loaded.neutral()), shown.extra_pose(loaded.extra_neutral())), svg_path, cell)
        click.echo(f"wrote {svg_path} ({expression} on {loaded.name})")
    if save_path:
        if not save_path.lower().endswith(".json"):
            raise click.BadParameter(f"{save_path}: expected a .json face file", param_hint="--save")
        from pathlib import Path

        saved = replace(loaded, name=new_name or Path(save_path).stem)
        save_face(saved, save_path)
        click.echo(f"wrote {save_path} ({saved.name}, from {loaded.name}: edit it, then --face {save_path})")
    if not sheet_path and not svg_path and not save_path:
        counts = f"{len(loaded.polygons)} polygons, {len(loaded.basic_components())} components"
        if loaded.extra_codes:
            counts += f"; parameters beyond the 21: {' '.join(loaded.extra_codes)}"
        click.echo(f"{loaded.name}: ok ({counts}); {loaded.description}")


for _command in (*MAPPING_COMMANDS, *PLAYER_COMMANDS, *ANIM_COMMANDS, *STREAM_COMMANDS, *BATCH_COMMANDS,
                 *LAYOUT_COMMANDS, *STUDIO_COMMANDS, *VOICE_COMMANDS, *OUTPUT_COMMANDS, *ROOM_COMMANDS):
    cli.add_command(_command)


def _terminate(signum: int, frame: object) -> None:
    raise Terminated()


def main(argv: list[str] | None = None) -> int:
    """Run the command line; returns the exit status.

    SIGTERM is raised as :class:`~common.errors.Terminated`, a KeyboardInterrupt: outputs are
    closed and kept as on Ctrl-C (a recording keeps what it has, a render what it drew).
    """
    keep_freed_memory()  # whole-take arrays reuse pages instead of faulting in fresh ones (common.memory)
    in_main_thread = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGTERM, _terminate) if in_main_thread else None
    try:
        return _main(argv)
    finally:
        if in_main_thread:
            signal.signal(signal.SIGTERM, previous)


def _main(argv: list[str] | None) -> int:
    debug = os.environ.get("TOONFACE_DEBUG") == "1"
    try:
        with warnings.catch_warnings():
            if not debug:  # numpy's overflow and empty-slice warnings are not the user's to read
                warnings.simplefilter("ignore", RuntimeWarning)
            status = cli.main(args=argv, prog_name="toonface", standalone_mode=False)
        if isinstance(status, int):  # ctx.exit(N) in a subcommand
            return status
    except click.exceptions.Exit as exc:
        return exc.exit_code
    except click.UsageError as exc:
        where = f" (see '{exc.ctx.command_path} --help')" if exc.ctx and exc.ctx.parent else ""
        click.echo(f"toonface: error: {exc.format_message()}{where}".replace("\n", " "), err=True)
        return 2
    except click.ClickException as exc:
        click.echo(f"toonface: error: {exc.format_message()}".replace("\n", " "), err=True)
        return exc.exit_code
    except click.Abort as exc:  # click turns KeyboardInterrupt (Ctrl-C, and SIGTERM here) into Abort
        stop = exc.__cause__
        if isinstance(stop, Interrupted):
            click.echo(f"toonface: {stop.signal_name}: kept {stop.output} with the {stop.frames} of "
                       f"{stop.total} frames drawn", err=True)
            return 143 if stop.signal_name == "SIGTERM" else 130
        click.echo("toonface: stopped (SIGTERM)" if isinstance(stop, Terminated) else "toonface: aborted", err=True)
        return 143 if isinstance(stop, Terminated) else 130
    except ToonfaceError as exc:
        if debug:
            raise
        click.echo(f"toonface: error: {exc}".replace("\n", " "), err=True)
        return 2
    except OSError as exc:
        if debug:
            raise
        where = f"{exc.filename}: " if exc.filename else ""
        click.echo(f"toonface: error: {where}{exc.strerror or exc}", err=True)
        return 2
    except Exception as exc:  # a bug: still one line for the user, the traceback on request
        if debug:
            raise
        click.echo(f"toonface: internal error: {type(exc).__name__}: {exc} (TOONFACE_DEBUG=1 shows the traceback)",
                   err=True)
        return 70
    return 0


if __name__ == "__main__":
    sys.exit(main())
