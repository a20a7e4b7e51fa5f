"""A video of a synthetic performer's dots, with the true 2-D positions, for testing trackers.

The performer's markers (millimetres, x to the performer's left, y up) are seen from the front
by an orthographic camera: ``u = cx + s x``, ``v = cy - s y`` pixels. Each visible marker is a
blue dot drawn anti-aliased at sub-pixel precision on a face-like textured background. Then, each
switchable and seeded: a blur, a slow lighting change (gain and a moving gradient), a hand that
passes in front of the lower face (the dots it covers are marked unseen in the truth), Gaussian
sensor noise and JPEG compression.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import cv2
import numpy as np

from capture.dots import sticker_labels
from capture.take import Take

DOT_BGR = (205, 90, 25)
SKIN_BGR = (120, 160, 215)
_SHIFT = 4  # cv2 drawing in 1/16 pixel


@dataclass(frozen=True)
class VideoFaults:
    """Image faults of the generated video; each can be switched off."""

    blur_sigma: float = 0.8
    noise_sigma: float = 3.0
    lighting: float = 0.25  # amplitude of the gain change
    jpeg_quality: int | None = 85
    hand: tuple[float, float] | None = (0.45, 0.65)  # the hand's passage, as fractions of the take


@dataclass(frozen=True, eq=False)
class DotVideo:
    """The truth behind a generated video.

    Attributes
    ----------
    labels : tuple of str
    pixels : ndarray, shape (frames, markers, 2)
        True dot centres (x right, y down), also where covered.
    visible : ndarray of bool, shape (frames, markers)
    rate : float
    pixels_per_mm : float
    size : (width, height)
    """

    labels: tuple[str, ...]
    pixels: np.ndarray
    visible: np.ndarray
    rate: float
    pixels_per_mm: float
    size: tuple[int, int]


def dot_video(take: Take, labels: list[str] | None = None, size: tuple[int, int] = (640, 480),
              faults: VideoFaults = VideoFaults(), dot_diameter_mm: float = 4.0, seed: int = 0
              ) -> tuple[DotVideo, Iterator[np.ndarray]]:
    """The truth of a dot video of ``take`` and an iterator over its BGR frames.

    ``labels`` defaults to every marker but the pupils (a sticker cannot sit on an eye).
    """
    chosen = sticker_labels(take.labels) if labels is None else list(labels)
    pos = take.select(chosen)
    width, height = size
    ppm = 0.8 * height / 190.0  # the face, chin to hairline plus margin, fills 80 % of the height
    centre = np.array([width / 2, height / 2 - 25.0 * ppm])  # y = -25 mm (the nose) at mid-height
    pixels = np.stack([centre[0] + ppm * pos[:, :, 0], centre[1] - ppm * pos[:, :, 1]], axis=-1)
    frames = take.frames
    hand_centre = np.full((frames, 2), np.nan)
    visible = np.isfinite(pixels).all(axis=2)
    if faults.hand is not None:
        start, end = (int(f * frames) for f in faults.hand)
        for f in range(start, end):
            progress = (f - start) / max(end - start - 1, 1)
            hand_centre[f] = (-0.2 * width + 1.4 * width * progress, height * 0.72)
        hand_radii = np.array([0.16 * width, 0.11 * height])
        inside = (((pixels - hand_centre[:, None]) / hand_radii) ** 2).sum(axis=2) <= 1.0 + 0.25
        visible &= ~np.nan_to_num(inside, nan=0.0).astype(bool)
    truth = DotVideo(tuple(chosen), pixels, visible, take.rate, ppm, size)
    return truth, _frames(truth, hand_centre, faults, dot_diameter_mm * ppm / 2, seed)


def _frames(truth: DotVideo, hand_centre: np.ndarray, faults: VideoFaults, radius: float,
            seed: int) -> Iterator[np.ndarray]:
    width, height = truth.size
    rng = np.random.default_rng(seed)
    background = _face_background(width, height, truth.pixels_per_mm, rng)
    ys = np.linspace(-1.0, 1.0, height, dtype=np.float32)[:, None, None]
    for f in range(len(truth.pixels)):
        image = background.copy()
        for x, y in truth.pixels[f]:  # every dot is drawn; the hand, drawn next, covers some
            if np.isfinite(x):
                cv2.circle(image, (round(x * 16), round(y * 16)), round(radius * 16), DOT_BGR, -1,
                           cv2.LINE_AA, _SHIFT)
        if np.isfinite(hand_centre[f]).all():
            cx, cy = hand_centre[f]
            cv2.ellipse(image, ((float(cx), float(cy)), (0.32 * width, 0.22 * height), 15.0), (95, 135, 190), -1,
                        cv2.LINE_AA)
        if faults.blur_sigma > 0:
            image = cv2.GaussianBlur(image, (0, 0), faults.blur_sigma)
        work = image.astype(np.float32)
        if faults.lighting:
            phase = 2 * np.pi * f / max(len(truth.pixels), 1)
            work *= 1.0 + faults.lighting * (0.6 * np.sin(phase) + 0.4 * ys * np.cos(2 * phase))
        if faults.noise_sigma > 0:
            work += rng.normal(0.0, faults.noise_sigma, size=work.shape).astype(np.float32)
        image = np.clip(work, 0, 255).astype(np.uint8)
        if faults.jpeg_quality is not None:
            _, buf = cv2.imencode(".jpg", image, [cv2.IMWRITE_JPEG_QUALITY, faults.jpeg_quality])
            image = np.asarray(cv2.imdecode(buf, cv2.IMREAD_COLOR))
        yield image


def _face_background(width: int, height: int, ppm: float, rng: np.random.Generator) -> np.ndarray:
    """A dark backdrop, a skin-coloured head with a mottled texture, eyebrows-like shading."""
    image = np.full((height, width, 3), (60, 55, 50), dtype=np.uint8)
    centre = (width // 2, int(height / 2 - 10 * ppm))
    cv2.ellipse(image, (centre, (int(150 * ppm), int(200 * ppm)), 0.0), SKIN_BGR, -1, cv2.LINE_AA)
    texture = cv2.GaussianBlur(rng.normal(0.0, 25.0, size=(height, width)).astype(np.float32), (0, 0), 6.0)
    image = np.clip(image.astype(np.float32) + texture[:, :, None], 0, 255).astype(np.uint8)
    for side in (-1, 1):  # darker eye sockets and lips: features the tracker must ignore
        cv2.ellipse(image, ((width / 2 + side * 32 * ppm, height / 2 - 25 * ppm), (24 * ppm, 12 * ppm), 0.0),
                    (90, 115, 160), -1, cv2.LINE_AA)
    cv2.ellipse(image, ((width / 2, height / 2 - 25 * ppm + 70 * ppm), (44 * ppm, 12 * ppm), 0.0), (80, 80, 170), -1,
                cv2.LINE_AA)
    return image


def score_tracking(pixels: np.ndarray, truth: DotVideo) -> dict[str, float]:
    """How well tracked ``pixels`` ``(frames, markers, 2)`` follow ``truth``.

    Returns
    -------
    dict
        ``median_error_px`` over samples tracked while visible; ``found`` the share of visible
        samples tracked; ``invented`` the count of samples tracked while covered (should be 0
        beyond the hand's soft edge); ``swap_frames`` the share of frames where some track sits on
        another marker: within a quarter of their separation from the other's true position and
        further than three quarters from its own (markers closer than 3 px, such as the lids of a
        closed eye, cannot swap); ``gross_frames`` the share of frames with a track more than
        3 px from its own marker.
    """
    tracked = np.isfinite(pixels).all(axis=2)
    err = np.linalg.norm(pixels - truth.pixels, axis=2)
    good = tracked & truth.visible
    to_truth = np.linalg.norm(pixels[:, :, None] - truth.pixels[:, None, :], axis=3)  # (F, track, marker)
    sep = np.linalg.norm(truth.pixels[:, :, None] - truth.pixels[:, None, :], axis=3)
    with np.errstate(invalid="ignore"):
        on_other = (to_truth < 0.25 * sep) & (err[:, :, None] > 0.75 * sep) & (sep > 3.0)
    swaps = np.nan_to_num(on_other, nan=0.0).astype(bool).any(axis=(1, 2))
    gross = (np.nan_to_num(err, nan=0.0) > 3.0).any(axis=1)
    return {
        "median_error_px": float(np.median(err[good])) if good.any() else float("nan"),
        "found": float(good.sum() / max(truth.visible.sum(), 1)),
        "invented": int((tracked & ~truth.visible).sum()),
        "swap_frames": float(swaps.mean()) if len(swaps) else 0.0,
        "gross_frames": float(gross.mean()) if len(gross) else 0.0,
    }
