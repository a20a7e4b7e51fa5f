"""A clip as a fake camera for Chromium (``--use-file-for-fake-video-capture``): a Y4M file (the
performer page's bench, :mod:`bench.room_performer`, and its browser tests)."""

from __future__ import annotations

from pathlib import Path


def y4m_from(video: Path, out: Path, seconds: float | None = None) -> Path:
    """``video``'s frames (the first ``seconds`` of them) as a Y4M file at ``out``, 4:2:0, at
    the clip's frame rate, which Chromium plays as its camera, looping."""
    import av

    with av.open(str(video)) as container:
        stream = container.streams.video[0]
        rate = stream.average_rate or 25
        with out.open("wb") as f:
            header = False
            for frame in container.decode(stream):
                if seconds is not None and frame.time is not None and frame.time >= seconds:
                    break
                image = frame.reformat(format="yuv420p")
                if not header:
                    f.write(f"YUV4MPEG2 W{image.width} H{image.height} F{rate.numerator}:{rate.denominator} "
                            "Ip A1:1 C420jpeg\n".encode())
                    header = True
                f.write(b"FRAME\n")
                for plane, (w, h) in zip(image.planes, ((image.width, image.height),
                                                        (image.width // 2, image.height // 2),
                                                        (image.width // 2, image.height // 2)), strict=True):
                    data = bytes(plane)
                    for row in range(h):
                        f.write(data[row * plane.line_size:row * plane.line_size + w])
    return out
