"""The talking-face clips a voice's mouth is learned from and judged on, and the truth in each.

Every shared clip with sound (``../shared/realdata/video/talking`` and ``grid``) carries its own
truth: the mouth the face tracker (:func:`capture.video_tracking.track_video`, MediaPipe's face
landmarker) measures in the same frames. The opening is the inner-lip gap over the distance
between the outer eye corners (so that a head coming nearer does not open the mouth), put on the
sound's 100 Hz clock. Clips are grouped by speaker (two VoxCeleb clips show the same man) and by
corpus: ``grid`` (GRID, a studio), ``studio`` (video-retalking's inputs: a person addressing a
camera, studio sound) and ``wild`` (VoxCeleb2 crops: interviews and television, noise and music).
Other GRID speakers are kept for an outside check and are never read here. Beside the shared
clips, ``bench/talking`` holds two more VoxCeleb2 crops of two more speakers, found for the voice's
model (their source and licence: ``bench/talking/SOURCES.md``); they count as ``wild``.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from bench.core import REALDATA

VIDEO = REALDATA / "video"
#: Talking-face clips found beside the shared ones (``SOURCES.md`` there).
OURS = Path(__file__).resolve().parent / "talking"
#: Clips of one speaker under another name.
SAME_SPEAKER = {"vox-741400163": "vox-00104"}


def clips(ours: bool = False) -> list[Path]:
    """Every shared talking-face clip with sound, in a fixed order (empty where the folder is
    absent); with ``ours``, then those of :data:`OURS` (after the shared ones, so that each shared
    clip's seeded augmentation stays what it was)."""
    shared = sorted((VIDEO / "talking").glob("*.mp4")) + sorted((VIDEO / "grid").glob("*.mpg"))
    return shared + (sorted(OURS.glob("*.mp4")) if ours and shared else [])


def speaker(clip: Path | str) -> str:
    """The speaker of a clip (its name, unless another clip shows the same person)."""
    name = Path(clip).stem
    return SAME_SPEAKER.get(name, name)


def corpus(clip: Path | str) -> str:
    """``grid``, ``studio`` or ``wild`` (see the module docstring)."""
    name = Path(clip).stem
    return "wild" if name.startswith("vox-") else "studio" if name.startswith("retalking-") else "grid"


@dataclass(frozen=True)
class Clip:
    """One clip's sound and the mouth tracked in it.

    Attributes
    ----------
    name, speaker, corpus : str
    sound : ndarray, shape (samples,)
        16 kHz mono.
    video_times : ndarray, shape (frames,)
        The video frames' times on the sound's clock, seconds.
    gap : ndarray, shape (frames,)
        The inner-lip gap over the outer eye corners' distance; NaN where no face was found.
    """

    name: str
    speaker: str
    corpus: str
    sound: np.ndarray
    video_times: np.ndarray
    gap: np.ndarray

    @property
    def frames(self) -> int:
        """Sound frames of 10 ms."""
        return len(self.sound) // 160

    def target(self) -> np.ndarray:
        """The gap on the sound's 100 Hz clock, ``(frames,)``, scaled so that the clip's 5th and
        95th percentiles are 0 and 1 (a speaker's own shut and wide open)."""
        seen = np.isfinite(self.gap)
        gap = np.interp(np.arange(self.frames) / 100.0, self.video_times[seen], self.gap[seen])
        low, high = np.percentile(gap, [5.0, 95.0])
        return (gap - low) / max(high - low, 1e-9)


def load_clip(path: Path) -> Clip:
    """The clip at ``path``, its face tracked (a few seconds a clip)."""
    from capture.video_tracking import track_video
    from capture.voice import decode_voice_at

    sound, start = decode_voice_at(path)
    take = track_video(path, "face")
    at = {name: take.labels.index(name) for name in ("LIP_UP_IN", "LIP_LOW_IN", "EYE_R_OUT", "EYE_L_OUT")}
    p = take.positions
    eyes = np.linalg.norm(p[:, at["EYE_R_OUT"]] - p[:, at["EYE_L_OUT"]], axis=1)
    gap = np.abs(p[:, at["LIP_LOW_IN"], 1] - p[:, at["LIP_UP_IN"], 1]) / eyes
    return Clip(path.stem, speaker(path), corpus(path), sound, take.times - start, gap)
