"""The ``markerset`` subcommands: a marker set for a layout toonface has not seen."""

from __future__ import annotations

import json
import re
from pathlib import Path

import click
import numpy as np

from toonface.cli_options import TakeReading, check_output, read_take, take_options

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


@click.group()
def markerset() -> None:
    """Marker sets for layouts toonface has not seen (docs/howto/own-layout.md)."""


@markerset.command("draft")
@click.argument("take", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False), help="Marker set to write (.toml).")
@click.option("--up", default=None, metavar="MARKER",
              help="A marker above the face's middle (on the forehead): settles which way is up where the "
                   "take's motion cannot [default: found from the jaw, brows and mouth corners].")
@click.option("--front", default=None, metavar="MARKER",
              help="A marker on the front of the face (the nose): settles which way the face points where "
                   "its shape cannot [default: the side where the midline stands out].")
@click.option("--name", default=None, help="The marker set's name [default: the output file's stem].")
@take_options
def draft(take: str, output: str, up: str | None, front: str | None, name: str | None, reading: TakeReading) -> None:
    """Draft a marker set from a take: head references, head-frame axes and every neutral.

    The head references are the largest group of markers that stay rigid together; x is the
    normal of the face's plane of mirror symmetry, y the line of its midline markers (else the
    main direction of its motion), up where the jaw opens from and the brows rise to, z out of
    the face. A layout in any frame and any units the face's size can tell works without --up;
    where the data cannot tell, a warning says so and names the option. Check the draft with
    `toonface info TAKE --plot markers.png --markerset DRAFT` and edit it: its comments say
    what was found. Use a take with expressions and speech, so that the moving markers show
    themselves.
    """
    from capture.draft import draft_markerset
    from capture.markerset import load_markerset
    from common import atomic_path

    if not output.lower().endswith(".toml"):
        raise click.BadParameter(f"{output}: a marker set is a .toml file", param_hint="--output")
    check_output(output, "--output")
    loaded = read_take(take, reading)
    found = draft_markerset(loaded, up, front)
    title = name or Path(output).stem
    tables = {key: value for key, value in (("rate", reading.rate), ("units", reading.units)) if value is not None}
    with atomic_path(output) as tmp:
        tmp.write_text(_toml(found, title, Path(take).name, up) + _tables(tables), encoding="utf-8")
    written = load_markerset(output)  # the draft must load, and look like head-frame millimetres
    click.echo(f"wrote {output}: {len(found.labels)} markers, "
               + (f"head references {', '.join(found.head_reference)}" if found.head_reference
                  else "no head references (a jaw and the mouth corners: head motion is not removed)"))
    for doubt in (*found.frame.doubts, *written.doubts()):
        click.echo(f"warning: {doubt}", err=True)


def _key(label: str) -> str:
    return label if _BARE_KEY.match(label) else json.dumps(label)


def _toml(found, title: str, source: str, up: str | None) -> str:
    axes = ", ".join(f"{n} = ({', '.join(f'{v:+.3f}' for v in row)})" for n, row in zip("xyz", found.rotation,
                                                                                          strict=True))
    frame = found.frame
    votes = {1: "agrees", -1: "disagrees", 0: "cannot tell"}
    how = [f"#   x: the face mirrors across its midline to within {frame.symmetry_mm:.1f} mm on average;",
           f"#   y: {frame.vertical:.0%} of the face's motion in the midline plane is along its main direction;",
           "#   up: " + (f"set by {up}." if up else f"the skull above the jaw {votes[frame.up_votes[0]]}, the largest "
                         f"mover's travel from rest {votes[frame.up_votes[1]]};"),
           f"#   front: the midline stands {frame.front_mm:.0f} mm out from the sides."]
    if not found.head_reference:
        how = ["#   x: from the right mouth corner to the left (the two the third marker lies equally far from);",
               "#   y: up, against the way the jaw marker travels from the corners when it opens;",
               f"#   z: toward the jaw marker, {frame.front_mm:.0f} mm in front of the corners' line."]
    lines = [
        f"# A draft marker set from {source} (toonface markerset draft). Check it before use:",
        f"#   toonface info {source} --plot markers.png --markerset THIS_FILE",
        "# Head frame, in the take's axes: " + axes + "; origin on the midline at the head references' centroid.",
        "# x points to the performer's left, y up, z out of the face. How each was found:",
        *how,
        *[f"# DOUBT: {doubt}" for doubt in frame.doubts],
        "# Head references: the largest group of markers that stay rigid together. Each marker's",
        "# steadiness (the median variation, mm, of its distances to the others) is in its comment:",
        "# markers on the skull have the smallest.",
        'format = "toonface.markerset/1"',
        f"name = {json.dumps(title)}",
        f"description = {json.dumps(f'drafted from {source}')}",
        "head_reference = [" + ", ".join(json.dumps(r) for r in found.head_reference) + "]",
        "",
        "[markers]",
    ]
    for label, point in zip(found.labels, found.neutral, strict=True):
        if not np.isfinite(point).all():
            lines.append(f"# {label}: never seen in the take")
            continue
        values = ", ".join(f"{v:.2f}" for v in point)
        lines.append(f"{_key(label)} = {{ neutral = [{values}] }}  # steadiness {found.steadiness[label]:.2f} mm")
    return "\n".join(lines) + "\n"


def _tables(given: dict) -> str:
    """The ``[tables]`` section: the rate and units the draft's take was read with, which every
    later command reading a table of this rig then takes without --rate and --units."""
    if not given:
        return ""
    lines = ["", "# How this rig's tables were read: commands given this set (or a mapping for it) read its",
             "# tables so, where a table and the options do not say.", "[tables]"]
    for key, value in given.items():
        lines.append(f"{key} = {value!r}" if key == "rate" else f"{key} = {json.dumps(str(value))}")
    return "\n".join(lines) + "\n"


LAYOUT_COMMANDS = (markerset,)


@markerset.command("match")
@click.argument("take", type=click.Path(dir_okay=False))
@click.option("--markerset", "layout", required=True, metavar="NAME|FILE", help="The marker set to match to.")
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False),
              help="The take's marker names in column order, one per line, for --labels @FILE.")
@take_options
def match(take: str, layout: str, output: str, reading: TakeReading) -> None:
    """Name a take's markers after a marker set's by the shape of their neutrals.

    For a second take of a layout whose columns come in another order (a headerless CSV: give
    any --labels, such as the first take's names). Writes the names in the take's column order;
    read the take again with --labels @OUTPUT. Markers far from their match are listed.
    """
    from capture.draft import match_layout
    from capture.markerset import load_markerset
    from common import atomic_path

    check_output(output, "--output")
    loaded = read_take(take, reading)
    target = load_markerset(layout)
    found = match_layout(loaded, target.labels, target.neutral)
    with atomic_path(output) as tmp:
        tmp.write_text("\n".join(found.labels) + "\n", encoding="utf-8")
    click.echo(f"wrote {output}: {len(found.labels)} markers matched to {target.name}, "
               f"{found.rms_mm:.1f} mm RMS after the best rigid fit")
    far = [f"{label} ({d:.0f} mm)" for label, d in zip(found.labels, found.distance, strict=True) if d > MATCH_DOUBT_MM]
    if far:
        click.echo(f"warning: far from their match, check them: {', '.join(far)}", err=True)


@markerset.command("mapping")
@click.argument("layout", metavar="MARKERSET.toml", type=click.Path(dir_okay=False))
@click.option("-o", "--output", required=True, type=click.Path(dir_okay=False), help="Mapping to write (.toml).")
@click.option("--take", "take_path", default=None, type=click.Path(dir_okay=False),
              help="A take of the layout with expressions and speech: the jaw, the mouth corners and the brows "
                   "are also found from how they move, for motors no preset's markers gave.")
@take_options
def mapping_cmd(layout: str, output: str, take_path: str | None, reading: TakeReading) -> None:
    """Draft a mapping for a marker set from the built-in presets.

    Each preset's marker set is laid over yours (a scale, an offset and a turn of a few degrees
    in the head frame); the markers its rules read are found by position, and the preset that
    finds the most gives the draft; a motor found on one side only is mirrored from its twin.
    With --take, the jaw, the mouth corners and the brows are also found from how they move,
    for the motors the presets left out. Motors still missing are listed; a draft that drives
    fewer than 8 of the face's motors, or not the jaw, is a warning.
    """
    import os

    import tomli_w

    from capture.markerset import load_markerset
    from common import atomic_path
    from mapping.draft import draft_mapping
    from mapping.mapfile import load_mapping

    if not output.lower().endswith(".toml"):
        raise click.BadParameter(f"{output}: a mapping is a .toml file", param_hint="--output")
    check_output(output, "--output")
    target = load_markerset(layout)
    reference = os.path.relpath(Path(layout).resolve(), Path(output).resolve().parent)
    found = draft_mapping(target, reference)
    if take_path is not None and target.head_reference:
        found = _with_motion_roles(found, target, read_take(take_path, reading, layout))
    pairs = ", ".join(f"{mine} = {theirs}" for theirs, mine in sorted(found.found.items(), key=lambda p: p[1]))
    header = (f"# A draft mapping for {Path(layout).name} (toonface markerset mapping), following the "
              f"{found.template} preset.\n# Its markers found by position ({found.fit_mm:.1f} mm apart on average "
              f"after the fit): {pairs}.\n"
              + (f"# Left out (markers not found): {', '.join(found.unmapped)}.\n" if found.unmapped else ""))
    with atomic_path(output) as tmp:
        tmp.write_text(header + tomli_w.dumps(found.doc), encoding="utf-8")
    load_mapping(output)  # the draft must load
    from toon import MOTOR_CODES

    extras = [code for code in found.doc["motor"] if code not in MOTOR_CODES]  # HT: a parameter, not a motor
    click.echo(f"wrote {output}: {len(found.doc['motor']) - len(extras)} motors"
               f"{' and ' + ', '.join(extras) if extras else ''} after the {found.template} preset"
               + (f"; left out: {', '.join(found.unmapped)}" if found.unmapped else ""))
    face = [code for code in found.doc["motor"] if code in MOTOR_CODES and code not in ("HH", "HV")]
    if len(face) < MIN_DRAFTED_MOTORS or "MB" not in face:  # 3 motors mapped, then a still face in silence
        missing = [code for code in ("MB", "MLH", "MRH", "BLC", "BRC", "ELU", "ERU") if code not in face]
        why = ("a jaw and the mouth corners show no brows or lids, and the corners' heights (MLV, MRV) move with "
               "the head" if not target.head_reference else
               "no preset's markers for them lie near yours. Check the marker set's axes (info --plot --markerset) "
               "and write those rules by hand")
        click.echo(f"warning: the draft drives {len(face)} of the face's motors ({', '.join(face) or 'none'}); "
                   f"not {', '.join(missing)}: {why}", err=True)


def _with_motion_roles(found, target, take):
    """``found`` (a :class:`~mapping.draft.MappingDraft`) with the motors it left out that the
    take's motion gives (:func:`mapping.roles.motion_roles`), said on the terminal."""
    from dataclasses import replace

    from capture.plot import in_head_frame
    from mapping.roles import motion_roles

    placed = in_head_frame(take, target)
    columns = target.match(placed.labels)
    local = np.full((placed.frames, len(target.labels), 3), np.nan)
    for k, label in enumerate(target.labels):
        if label in columns:
            local[:, k] = placed.positions[:, placed.labels.index(columns[label])]
    roles = motion_roles(target, local)
    added = {code: rule for code, rule in roles.items() if code not in found.doc["motor"]}
    if not added:
        return found
    click.echo(f"found from the take's motion: {', '.join(added)}")
    source = take.meta.get("file", "a take")
    doc = {**found.doc, "motor": {**found.doc["motor"], **added},
           "description": f"{found.doc['description']}; {', '.join(added)} found from the motion of {source}"}
    return replace(found, doc=doc, unmapped=tuple(code for code in found.unmapped if code not in added))


#: A drafted mapping driving fewer of the face's motors than this (or not MB) is a warning.
MIN_DRAFTED_MOTORS = 8
#: A column further than this (mm) from its matched neutral is listed for checking.
MATCH_DOUBT_MM = 5.0
