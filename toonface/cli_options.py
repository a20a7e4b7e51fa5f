"""Options and helpers shared by the ``toonface`` subcommands."""

from __future__ import annotations

import functools
import math
import os
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from mapping.settings import HOLD_SECONDS, MAX_GAP_SECONDS

if TYPE_CHECKING:
    from capture import Take


class FiniteFloat(click.FloatRange):
    """A number option that refuses NaN and infinities by name, within optional bounds as
    :class:`click.FloatRange` (``clean --max-gap nan`` ended in "internal error", and some
    options wrote a file the reader then rejected)."""

    name = "number"

    def convert(self, value, param, ctx):  # click's signature
        number = super().convert(value, param, ctx)
        if not math.isfinite(number):
            self.fail(f"{value!r} is not a finite number", param, ctx)
        return number

    def _describe_range(self) -> str:
        """The bounds for ``--help``; nothing where there are none (click wrote "x<=None")."""
        return "" if self.min is None and self.max is None else super()._describe_range()


class ProgressBar:
    """A per-frame progress callback drawing a bar on stderr (only when stderr is a terminal)."""

    def __init__(self, total: int, desc: str, unit: str = "frame") -> None:
        from tqdm import tqdm

        self.total = total
        self.bar = tqdm(total=total, desc=desc, unit=unit, file=sys.stderr, disable=None, leave=False)

    def __call__(self, frames: int) -> None:
        self.bar.update(frames)
        if self.bar.n >= self.total:
            self.bar.close()


def progress(desc: str, unit: str = "frame") -> Callable[[int], Callable[[int], None]]:
    """A factory of progress callbacks, given the total number of frames (or ``unit``)."""
    return lambda total: ProgressBar(total, desc, unit)


def frame_size(value: str) -> tuple[int, int]:
    """``N`` or ``WxH`` pixels as ``(width, height)``, each side 16..8192; a ValueError says what is wrong."""
    try:
        w, x, h = value.lower().partition("x")
        size = (int(w), int(h if x else w))  # "100x" names no height: refused
    except ValueError:
        raise ValueError(f"expected N or WxH pixels, got {value!r}") from None
    if not (16 <= size[0] <= 8192 and 16 <= size[1] <= 8192):
        raise ValueError(f"each side must be 16..8192 pixels, got {value!r}")
    return size


def parse_size(value: str, option: str = "--size") -> tuple[int, int]:
    """``N`` or ``WxH`` pixels (see :func:`frame_size`), for an option."""
    try:
        return frame_size(value)
    except ValueError as exc:
        raise click.BadParameter(str(exc), param_hint=option) from None


def check_output(path: str | None, option: str) -> None:
    """Refuse, before any work, an output whose folder does not exist (written at the end)."""
    if path is not None and path != "-" and not Path(path).resolve().parent.is_dir():
        raise click.BadParameter(f"{path}: no such folder {Path(path).parent}", param_hint=option)


def fresh_recording(path: str | None, force: bool, say: Callable[[str], None]) -> str | None:
    """Where a live command's ``--record`` goes: ``path``, unless a file is there and not
    ``force``: then the first free ``STEM_2.EXT``, ``STEM_3.EXT``..., said (a live take cannot be
    made again, so an earlier recording is never overwritten by a new run's)."""
    if path is None or force or not Path(path).exists():
        return path
    given = Path(path)
    number = 2
    while (free := given.with_name(f"{given.stem}_{number}{given.suffix}")).exists():
        number += 1
    say(f"{path} exists (an earlier recording): recording to {free} (--force overwrites)")
    return str(free)


FORCE_RECORD = click.option("--force", is_flag=True, help="--record overwrites a file of that name "
                                                          "[default: a new name beside it].")


def parse_codes(value: str | None, option: str = "--motors", also: tuple[str, ...] = (),
                any_parameter: bool = False) -> tuple[str, ...] | None:
    """Motor codes from ``CODE,CODE,...`` (any case); None for no value. Known: the 21, the
    standard parameters beyond them (HT...), ``also`` (those of the file at hand), and with
    ``any_parameter`` any code shaped like a parameter (a knot that starts a face's own); others
    are refused."""
    import re

    from toon.motors import ALL_CODES, EXTRA_CODE

    if not value:
        return None
    codes = tuple(c.strip().upper() for c in value.split(",") if c.strip())
    known = (*ALL_CODES, *(c for c in also if c not in ALL_CODES))
    unknown = [c for c in codes if c not in known and not (any_parameter and re.fullmatch(EXTRA_CODE, c))]
    if unknown or not codes:
        raise click.BadParameter(f"unknown motor code(s) {', '.join(unknown) or repr(value)} (known: "
                                 f"{' '.join(known)})", param_hint=option)
    return codes


def parse_window(value: str | None, option: str = "--neutral", words: tuple[str, ...] = ()
                 ) -> tuple[float, float] | str | None:
    """``START:END`` seconds, or one of ``words`` (None stays None)."""
    if value is None or value in words:
        return value
    return parse_span(value, option, words)


def parse_span(value: str | None, option: str, words: tuple[str, ...] = ()) -> tuple[float, float] | None:
    """``START:END`` seconds (None stays None); ``words`` are named in the error as other choices."""
    if value is None:
        return None
    try:
        start, end = (float(x) for x in value.split(":"))
    except ValueError:
        also = "".join(f" or {w}" for w in words)
        raise click.BadParameter(f"expected START:END in seconds{also}, got {value!r}", param_hint=option) from None
    if not end > start >= 0:
        raise click.BadParameter(f"expected 0 <= START < END, got {value!r}", param_hint=option)
    return start, end


@dataclass(frozen=True)
class TakeReading:
    """How to read a take: what a CSV table may not say about itself (``rate``, ``labels``,
    ``units``), and whether a C3D file that ends early may be read as far as it goes."""

    rate: float | None = None
    labels: str | None = None  # comma-separated
    units: str | None = None
    allow_truncated: bool = False
    words: str | None = None  # a voice's words, read from @FILE already
    listen: str | None = None  # how a voice is heard (capture.voice_take.LISTEN_MODES), None for the default


def take_options(fn: Callable) -> Callable:
    """--rate, --labels, --units, --allow-truncated, --text and --listen, handed to the command
    as one :class:`TakeReading` argument named ``reading``."""

    @functools.wraps(fn)
    def command(*args, take_rate: float | None, labels: str | None, units: str | None, allow_truncated: bool,
                text: str | None, listen: str | None, **kwargs):
        words = read_words(text) if text is not None else None
        return fn(*args, reading=TakeReading(take_rate, labels, units, allow_truncated, words, listen), **kwargs)

    command = LISTEN(command)
    command = click.option("--text", default=None, metavar="WORDS|@FILE",
                           help="A voice (a sound file) only: the words spoken (or @FILE holding them), aligned "
                                "with the sound, which places each mouth shape far more surely than the phones "
                                "heard without them.")(command)
    command = click.option("--allow-truncated", is_flag=True,
                           help="C3D: read a file that ends before the last frame its header declares, "
                                "with a warning, instead of refusing it.")(command)
    command = click.option("--units", default=None, metavar="mm|cm|m|in|N",
                           help="CSV only: the table's units, or millimetres per unit [default: mm].")(command)
    command = click.option("--labels", default=None, metavar="A,B,...|@FILE",
                           help="CSV only: marker names of a table without a header row, or @FILE to read "
                                "them from a file (one per line or comma-separated).")(command)
    return click.option("--rate", "take_rate", default=None, type=FiniteFloat(), metavar="HZ",
                        help="CSV only: frame rate of a table without a time column.")(command)


#: How a voice is heard; shared by every command that reads one.
LISTEN = click.option(
    "--listen", default=None, type=click.Choice(("sound", "words", "phones")),
    help="A voice only: how to hear it without --text. 'sound' (the default) reads how open and how round "
         "the mouth is from the sound's spectrum, in any language, 100 times faster than real time; 'words' "
         "(English) recognises the words said and opens the mouth from their phones and the sound as learned "
         "from real talking faces: the closest to real lips on English speech, about twice as fast as real "
         "time; 'phones' recognises US-English phones alone (pocketsphinx), which names each shape but "
         "follows the jaw less well.")


def _at_file(value: str, option: str, what: str) -> str:
    """The text an ``@FILE`` option value names, or the value itself; a file that cannot be read
    is the option's one-line error."""
    if not value.startswith("@"):
        return value
    from common import InputError
    from common.limits import read_regular_text

    path = Path(value[1:])
    try:
        return read_regular_text(path)
    except InputError as exc:
        raise click.BadParameter(f"cannot read {what}: {exc}", param_hint=option) from None


def read_words(text: str) -> str:
    """The words a voice speaks, from ``WORDS`` or ``@FILE``, on one line."""
    from capture.voice_text import words_of

    text = _at_file(text, "--text", "the words")
    if not words_of(text):  # (punctuation alone is no words either)
        raise click.BadParameter("no words given", param_hint="--text")
    return " ".join(text.split())


def _labels(value: str) -> list[str]:
    """Marker names from ``A,B,...`` or ``@FILE`` (names one per line or comma-separated; ``#``
    starts a comment)."""
    if not value.startswith("@"):
        return [x.strip() for x in value.split(",") if x.strip()]
    lines = [line.split("#", 1)[0] for line in _at_file(value, "--labels", "the names").splitlines()]
    return [name.strip() for line in lines for name in line.split(",") if name.strip()]


def read_take(path: str, reading: TakeReading = TakeReading(), layout: str | None = None,
              mapping: str | None = None) -> Take:
    """Load a take as the --rate/--labels/--units/--allow-truncated options say; a CSV table's
    rate and units, where neither it nor the options say them, from the ``[tables]`` of the
    marker set named by ``layout`` or read by ``mapping`` (a drafted set keeps the rig's)."""
    from capture import load_markerset, load_take
    from capture.sources import VIDEO_SUFFIXES

    if Path(path).suffix.lower() in VIDEO_SUFFIXES:
        return _tracked(path, reading)
    names = _labels(reading.labels) if reading.labels else None
    markerset = None
    if Path(path).suffix.lower() in (".csv", ".tsv", ".txt") and (reading.rate is None or reading.units is None):
        if mapping is not None and layout is None:
            from mapping.mapfile import load_mapping

            layout = load_mapping(mapping).markerset
        markerset = load_markerset(layout) if layout is not None else None
    return load_take(path, rate=reading.rate, labels=names, units=reading.units,
                     allow_truncated=reading.allow_truncated, markerset=markerset, words=reading.words,
                     listen=reading.listen)


def _tracked(path: str, reading: TakeReading) -> Take:
    """A talking-head video read as a take: its face tracked without markers, with a progress bar
    (:func:`capture.takefile.load_take_or_video`); the options for tables and voices refused."""
    from capture.takefile import load_take_or_video
    from common import InputError

    given = [option for option, value in (("--rate", reading.rate), ("--labels", reading.labels),
                                          ("--units", reading.units), ("--text", reading.words),
                                          ("--listen", reading.listen)) if value is not None]
    if given or reading.allow_truncated:
        named = ", ".join(given + (["--allow-truncated"] if reading.allow_truncated else []))
        raise InputError(f"{named}: not for a video, whose face is tracked at its own rate and in its own units "
                         "(--text and --listen are for a sound file)", path)
    return load_take_or_video(path, progress_factory=progress("track"))


BACKGROUND = click.option(
    "--background", default=None, metavar="none|#RRGGBB[AA]",
    help="The picture's background instead of the face's own: 'none' for transparent (kept by .webm, .mov, "
         ".apng, .webp and PNG folders; antialiased edges without a dark fringe), or a colour.")


VIRTUAL_CAMERA = click.option(
    "--virtual-camera", is_flag=True,
    help="Also send the face to a virtual webcam (Zoom, Meet, Teams, OBS take it as a camera): the first "
         "device found; -o vcam:/dev/videoN names one. Needs pyvirtualcam (pip install 'toonface[vcam]') and a "
         "v4l2loopback device on Linux, OBS's virtual camera on Windows and macOS.")


def with_background(face: Any, value: str | None) -> Any:
    """``face`` (a :class:`toon.Face`) with the ``--background`` given (``none``: transparent)."""
    import dataclasses
    import re

    if value is None:
        return face
    if value.lower() in ("none", "transparent"):
        return dataclasses.replace(face, background=(*face.background[:3], 0.0))
    match = re.fullmatch(r"#?([0-9a-fA-F]{6})([0-9a-fA-F]{2})?", value.strip())
    if match is None:
        raise click.BadParameter(f"expected none or a colour #RRGGBB or #RRGGBBAA, got {value!r}",
                                 param_hint="--background")
    rgb, alpha = match.group(1), match.group(2)
    return dataclasses.replace(face, background=(int(rgb[0:2], 16) / 255, int(rgb[2:4], 16) / 255,
                                                 int(rgb[4:6], 16) / 255, int(alpha, 16) / 255 if alpha else 1.0))


LIFE = click.option(
    "--life/--no-life", default=None,
    help="The life layer on the motors the source does not drive (live: or loses): blinks at pauses, gaze that "
         "holds and jumps, brows raised on pitch accents, nods on stressed syllables, sway and breathing (seeded: "
         "the same every run). On by default for a voice alone, off for other sources.")
EYE_CONTACT = click.option(
    "--eye-contact", is_flag=True,
    help="After the rest (the first second), look at the middle of your screen for a second: that look becomes "
         "the pupils' centre, so that the cartoon looks at its viewer while you look at the screen (a camera above "
         "it sees you look down) and still looks away when you do. Said when taken, or why not.")
LIVE_MAX_GAP = click.option(
    "--max-gap", default=MAX_GAP_SECONDS, show_default=True, type=FiniteFloat(min=0.0),
    help="A lost marker is filled for up to this many seconds, regressed on the markers seen (as map --max-gap "
         "fills, from the past alone); longer it is lost (0: none is filled).")
LIVE_HOLD_GAP = click.option(
    "--hold-gap", default=HOLD_SECONDS, show_default=True, type=FiniteFloat(min=0.0),
    help="A lost marker that is not regressed (one a 'pair' rule reads, as toon32's brows, lids and pupils, which "
         "then follow the other side) or a lost blendshape channel holds its last value this long, at most "
         "--max-gap.")
NO_PHYSICS = click.option(
    "--no-physics", is_flag=True,
    help="Draw without the face's physics: nothing swings or settles after the motors (hair, beard, hat).")


def without_physics(face: Any, off: bool) -> Any:
    """``face`` (a :class:`toon.Face`) without its physics drivers where ``off`` (``--no-physics``)."""
    import dataclasses

    return dataclasses.replace(face, physics=()) if off else face


FACE = click.option("--face", default="classic", show_default=True, metavar="NAME|FILE",
                    help="A built-in face (see `toonface faces`) or a face JSON file.")
SIZE = click.option("--size", default="512", show_default=True, metavar="N|WxH", help="Frame size in pixels.")
MIRROR = click.option("--mirror", is_flag=True, help="Mirror image: the performer's right drives the character's left.")
VMC = click.option("--vmc", default=None, metavar="HOST:PORT|PORT",
                   help="Listen for a face-tracking app over the VMC protocol (blendshapes and the head bone; "
                        "loopback, port 39539 by default: --vmc 39539), mapped with the arkit preset.")


VMC_OUT = click.option("--vmc-out", default=None, metavar="HOST:PORT",
                       help="Also send the motors shown to a VMC receiver (OSC over UDP): the 21 motors by code, "
                            "ARKit blendshapes where one motor gives one, the head bone; 39539 if no port.")


OPENSEEFACE = click.option("--openseeface", default=None, metavar="HOST:PORT|PORT",
                           help="Listen for OpenSeeFace's tracker (its UDP packets: features, eyes, head; loopback, "
                                "port 11573 by default), mapped with the arkit preset.")


def bridge_spec(source: str | None, vmc: str | None, openseeface: str | None = None,
                required: bool = True) -> str | None:
    """The source spec a positional SOURCE or a bridge option (``--vmc``, ``--openseeface``)
    names: exactly one of them (or none, where ``required`` is false)."""
    given = [spec for spec in (source, None if vmc is None else f"vmc:{vmc}",
                               None if openseeface is None else f"openseeface:{openseeface}") if spec is not None]
    if len(given) > 1:
        raise click.BadParameter("give one of a SOURCE, --vmc and --openseeface", param_hint="--vmc")
    if not given and required:
        raise click.UsageError("give a SOURCE (a take, a video, camera:N, synthetic), --vmc HOST:PORT or "
                               "--openseeface HOST:PORT")
    return given[0] if given else None


KEY = click.option("--key-file", default=None, type=click.Path(dir_okay=False, exists=True),
                   help="Shared secret (the file's bytes, 16 or more): packets are encrypted and authenticated "
                        "(AES-256-GCM-SIV), others and replays are dropped. Or set TOONFACE_STREAM_KEY.")


def stream_key(path: str | None) -> bytes | None:
    """The stream's shared secret: the bytes of the --key-file ``path`` (16 or more), else
    ``TOONFACE_STREAM_KEY``'s, else None (an open stream)."""
    from common import InputError
    from common.limits import read_regular

    if path:
        try:
            secret = read_regular(path, 4096, "key file").strip()
        except InputError as exc:
            raise click.BadParameter(str(exc), param_hint="--key-file") from None
        if len(secret) < 16:
            raise click.BadParameter(f"{path}: a key needs at least 16 bytes", param_hint="--key-file")
        return secret
    env = os.environ.get("TOONFACE_STREAM_KEY")
    return env.encode() if env else None
