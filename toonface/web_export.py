"""The exported web player: a motor track on a face as one self-contained HTML file that plays
in any browser with no server (``toonface export web``).

The page (``studio/static/player.html``) draws the face itself, as the room's viewer page does:
the face's web rig (:mod:`toon.web_rig`) and the track's own samples travel in it as JSON, and
the page modules every page shares (``rig.js``, ``physics.js``, ``draw.js``, inlined) draw each
screen frame, linear between samples, the face's physics run on the track's samples as a render
runs them. It plays, pauses and scrubs; an embedded sound (Opus in WebM, a data URI) leads when
there is one. In transparent mode the page has no background and no controls, for OBS's browser
source.
"""

from __future__ import annotations

import base64
import dataclasses
import html
import io
import json
import os
from importlib import resources
from pathlib import Path

import numpy as np

from common import atomic_path
from toon import Face, FaceRig, MotorTrack
from toon.motors import N_MOTORS
from toon.params import drawable
from toon.web_rig import web_rig

#: The page modules the player inlines, in order.
SCRIPTS = ("draw.js", "rig.js", "physics.js")

#: The sound's rate and bit rate in the page (Opus, voice-grade stereo folded to mono).
SOUND_RATE, SOUND_KBPS = 48000, 48


def encoded_sound(path: str | os.PathLike, span: tuple[float, float] | None = None) -> bytes:
    """``path``'s sound (a sound file or a video's; only ``span``'s seconds where given) as Opus
    in a WebM, bytes for a data URI."""
    import av

    from common.sound import decode_mono

    samples, _, _ = decode_mono(path, SOUND_RATE)
    if span is not None:
        samples = samples[int(round(span[0] * SOUND_RATE)):int(round(span[1] * SOUND_RATE))]
    out = io.BytesIO()
    with av.open(out, "w", format="webm") as container:
        stream = container.add_stream("libopus", rate=SOUND_RATE)
        stream.layout = "mono"
        stream.bit_rate = SOUND_KBPS * 1000
        frame = av.AudioFrame.from_ndarray(np.asarray(samples, np.float32)[None], format="flt", layout="mono")
        frame.sample_rate = SOUND_RATE
        for packet in (*stream.encode(frame), *stream.encode(None)):
            container.mux(packet)
    return out.getvalue()


def player_page(track: MotorTrack, face: Face, size: tuple[int, int] = (512, 512),
                sound: str | os.PathLike | None = None, transparent: bool = False, paused: bool = False,
                title: str = "toonface", sound_span: tuple[float, float] | None = None) -> str:
    """The web player's HTML for ``track`` on ``face`` (see the module docstring).

    Parameters
    ----------
    track, face
        What to play, and on which face (a standard parameter the face does not declare is left
        out, as a render leaves it).
    size : (width, height)
        The face's size on the page, pixels.
    sound : path-like, optional
        A sound file (or a video with sound) to embed and play with the face.
    transparent : bool
        No background and no controls: the face alone, looping (for OBS's browser source).
    paused : bool
        Open paused at 0 s.
    title : str
        The page's title.
    sound_span : (start, end), optional
        Seconds of ``sound`` to embed (a trimmed track's), its start at the page's 0 s [default: all].
    """
    if transparent:
        face = dataclasses.replace(face, background=(*face.background[:3], 0.0))
    rig = FaceRig(face)
    kept, _, unknown = drawable(track.extra_codes, face.extra_codes)
    kept += unknown  # (one the face lacks and no face has: the rig's error names it, as a render's does)
    table = track.table()
    columns = [N_MOTORS + track.extra_codes.index(code) for code in kept]
    rows = [rig.full_values(row[:N_MOTORS], dict(zip(kept, row[columns].tolist(), strict=True))).round(6).tolist()
            for row in table]
    take = json.dumps({"rig": web_rig(rig), "rate": track.rate, "rows": rows, "size": list(size)},
                      separators=(",", ":")).replace("</", "<\\/")  # (a name may not close the script)
    duration = max(track.frames - 1, 1) / track.rate
    audio = ""
    if sound is not None:
        data = base64.b64encode(encoded_sound(sound, sound_span)).decode("ascii")
        audio = f'<audio id="sound" preload="auto" src="data:audio/webm;base64,{data}"></audio>'
    static = resources.files("toonface.studio.static")
    template = static.joinpath("player.html").read_text(encoding="utf-8")
    scripts = "\n".join(f"<script>\n{static.joinpath(name).read_text(encoding='utf-8')}</script>" for name in SCRIPTS)
    fields = {"{{TITLE}}": html.escape(title), "{{AUDIO}}": audio, "{{DURATION}}": f"{duration:.6g}",
              "{{WIDTH}}": str(size[0]), "{{HEIGHT}}": str(size[1]),
              "{{PAGE_BACKGROUND}}": "transparent" if transparent else "#f4f4f4",
              "{{BODY_CLASS}}": "transparent" if transparent else "", "{{START_PAUSED}}": "true" if paused else "false",
              "{{SCRIPTS}}": scripts}
    for key, value in fields.items():
        template = template.replace(key, value)
    return template.replace("{{TAKE}}", take)  # last: the take's own text is never read for fields


def export_web(track: MotorTrack, face: Face, output: str | os.PathLike, **options) -> Path:
    """Write :func:`player_page` to ``output``, atomically; ``options`` as it takes them."""
    output = Path(output)
    with atomic_path(output) as tmp:
        tmp.write_text(player_page(track, face, **options), encoding="utf-8")
    return output
