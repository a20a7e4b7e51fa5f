"""The exported web player: a motor track on a face as one self-contained HTML file that plays
in any browser with no server (``toonface export web``).

The face is the animated SVG of :mod:`toon.svg_anim` (the studio's drawing, :mod:`toon.svg`,
over time), inlined; the page (``studio/static/player.html``) plays, pauses and scrubs it with
SVG's own clock, and an embedded sound (Opus in WebM, a data URI) leads when there is one. In
transparent mode the page has no background and no controls, for OBS's browser source.
"""

from __future__ import annotations

import base64
import dataclasses
import html
import io
import os
from importlib import resources
from pathlib import Path

import numpy as np

from common import atomic_path
from player.offline import geometries
from toon import Face, FaceRig, MotorTrack
from toon.svg_anim import track_svg

#: The sound's rate and bit rate in the page (Opus, voice-grade stereo folded to mono).
SOUND_RATE, SOUND_KBPS = 48000, 48


def encoded_sound(path: str | os.PathLike) -> bytes:
    """``path``'s sound (a sound file or a video's) as Opus in a WebM, bytes for a data URI."""
    import av

    from common.sound import decode_mono

    samples, _, _ = decode_mono(path, SOUND_RATE)
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


def player_page(track: MotorTrack, face: Face, size: tuple[int, int] = (512, 512), fps: float = 30.0,
                sound: str | os.PathLike | None = None, transparent: bool = False, paused: bool = False,
                title: str = "toonface") -> str:
    """The web player's HTML for ``track`` on ``face`` (see the module docstring).

    Parameters
    ----------
    track, face
        What to play, and on which face.
    size : (width, height)
        The face's size on the page, pixels.
    fps : float
        Frames per second sampled from the track (the SVG interpolates between its keys).
    sound : path-like, optional
        A sound file (or a video with sound) to embed and play with the face.
    transparent : bool
        No background and no controls: the face alone, looping (for OBS's browser source).
    paused : bool
        Open paused at 0 s.
    """
    if transparent:
        face = dataclasses.replace(face, background=(*face.background[:3], 0.0))
    frames = list(geometries(track, FaceRig(face), fps))
    svg = track_svg(frames, fps, size)
    duration = max(len(frames) - 1, 1) / fps
    audio = ""
    if sound is not None:
        data = base64.b64encode(encoded_sound(sound)).decode("ascii")
        audio = f'<audio id="sound" preload="auto" src="data:audio/webm;base64,{data}"></audio>'
    template = resources.files("toonface.studio.static").joinpath("player.html").read_text(encoding="utf-8")
    fields = {"{{TITLE}}": html.escape(title), "{{SVG}}": svg, "{{AUDIO}}": audio, "{{DURATION}}": f"{duration:.6g}",
              "{{WIDTH}}": str(size[0]), "{{PAGE_BACKGROUND}}": "transparent" if transparent else "#f4f4f4",
              "{{BODY_CLASS}}": "transparent" if transparent else "", "{{START_PAUSED}}": "true" if paused else "false"}
    for key, value in fields.items():
        template = template.replace(key, value)
    return template


def export_web(track: MotorTrack, face: Face, output: str | os.PathLike, **options) -> Path:
    """Write :func:`player_page` to ``output``, atomically; ``options`` as it takes them."""
    output = Path(output)
    with atomic_path(output) as tmp:
        tmp.write_text(player_page(track, face, **options), encoding="utf-8")
    return output
