"""Coloured dots from video (stickers or paint, like CharToon's tracked blue dots).

Per frame: HSV colour segmentation, connected components, and a sub-pixel centroid of each dot
weighted by its colour saturation (so the blurred rim counts by how blue it is, not by a
threshold). Identities:

* **start** — on the first frame (or a chosen one, where the face is neutral) the marker set's
  neutral layout, seen from the front, is fitted to the dots by a similarity transform
  (scale, rotation, shift), alternating with optimal assignment (ICP with
  ``scipy.optimize.linear_sum_assignment``). The fitted scale gives millimetres per pixel.
* **follow** — each frame, every track's predicted position (constant velocity) is matched to
  the dots by optimal assignment with a gate; a track without a dot is carried by pyramidal
  Lucas-Kanade optical flow for up to ``max_flow_frames`` frames and is NaN after that, never
  guessed. A lost track is looked for again where the layout, fitted to the tracks still seen,
  puts it.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Iterable, Iterator
from dataclasses import dataclass

import cv2
import numpy as np
from scipy.optimize import linear_sum_assignment

from capture.colours import HUES
from capture.markerset import MarkerSet

_FAR = 1e9
#: Share of a layout's markers that must be found on the first frame to identify the dots.
MIN_IDENTIFIED = 0.75


@dataclass(frozen=True)
class DotStyle:
    """What a dot looks like: its hue range (OpenCV's 0-180; ``lo > hi`` wraps through red), the
    least saturation and brightness of its core, and its area in pixels."""

    hue: tuple[int, int] = HUES["blue"]
    min_saturation: int = 90
    min_value: int = 90
    min_area: int = 4
    max_area: int = 2000

    @staticmethod
    def named(colour: str) -> DotStyle:
        if colour not in HUES:
            raise ValueError(f"unknown dot colour {colour!r} (known: {', '.join(HUES)})")
        return DotStyle(hue=HUES[colour])


def sticker_labels(labels: Iterable[str]) -> list[str]:
    """The markers that can carry a dot sticker: all but the pupils (none sits on an eye)."""
    return [x for x in labels if not x.startswith("PUPIL")]


def front_layout(markerset: MarkerSet, labels: Iterable[str]) -> np.ndarray:
    """The ``labels``' neutral x, y in millimetres, shape ``(M, 2)``: the face seen from the front."""
    return np.array([markerset.neutral_of(x)[:2] for x in labels]).reshape(-1, 2)


def find_dots(image: np.ndarray, style: DotStyle = DotStyle()) -> np.ndarray:
    """Sub-pixel centres of the dots in a BGR image, shape ``(N, 2)`` (x right, y down)."""
    hsv = cv2.cvtColor(image, cv2.COLOR_BGR2HSV)
    lo, hi = style.hue
    if lo <= hi:
        mask = cv2.inRange(hsv, (lo, style.min_saturation, style.min_value), (hi, 255, 255))
    else:
        mask = cv2.bitwise_or(cv2.inRange(hsv, (lo, style.min_saturation, style.min_value), (180, 255, 255)),
                              cv2.inRange(hsv, (0, style.min_saturation, style.min_value), (hi, 255, 255)))
    try:
        count, labels = cv2.connectedComponents(mask, connectivity=8, ltype=cv2.CV_16U)
    except cv2.error:  # more than 65535 specks: a noise image, not dots; labels as float32 then
        count, labels = cv2.connectedComponents(mask, connectivity=8, ltype=cv2.CV_32S)
        labels = labels.astype(np.float32)
    if count <= 1:
        return np.empty((0, 2))
    # Each dot with a 2-pixel rim (where blur fades it out); a rim pixel between two dots goes to
    # one of them. connectedComponentsWithStats costs ten times connectedComponents here.
    grown = cv2.dilate(labels, np.ones((5, 5), np.uint8))
    np.copyto(grown, labels, where=mask > 0)  # a dot's own pixels stay its own
    points = cv2.findNonZero(grown).reshape(-1, 2)
    xs, ys = points[:, 0], points[:, 1]
    own = grown[ys, xs].astype(np.intp)
    area = np.bincount(own, weights=(labels[ys, xs] > 0), minlength=count)
    pixels = hsv[ys, xs]  # (N, 3) hue, saturation, value of the dots and their rims
    hue = pixels[:, 0].astype(np.int16)
    in_hue = (hue >= lo) & (hue <= hi) if lo <= hi else (hue >= lo) | (hue <= hi)
    weight = np.where(in_hue, pixels[:, 1].astype(np.float64) - style.min_saturation / 2, 0.0).clip(min=0.0)
    total = np.bincount(own, weights=weight, minlength=count)
    cx = np.bincount(own, weights=weight * xs, minlength=count)
    cy = np.bincount(own, weights=weight * ys, minlength=count)
    keep = (area >= style.min_area) & (area <= style.max_area) & (total > 0)
    keep[0] = False
    return np.column_stack([cx[keep] / total[keep], cy[keep] / total[keep]])


def fit_similarity(src: np.ndarray, dst: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """Least-squares ``dst ~ s R src + t`` (Umeyama) for 2-D points ``(N, 2)``: ``(s, R, t)``."""
    mu_s, mu_d = src.mean(axis=0), dst.mean(axis=0)
    a, b = src - mu_s, dst - mu_d
    u, sig, vt = np.linalg.svd(b.T @ a / len(src))
    d = np.sign(np.linalg.det(u @ vt)) or 1.0
    rot = u @ np.diag([1.0, d]) @ vt
    scale = (sig * [1.0, d]).sum() / max((a ** 2).sum() / len(src), 1e-12)
    return float(scale), rot, mu_d - scale * rot @ mu_s


def _assign(predicted: np.ndarray, dots: np.ndarray, gate: np.ndarray) -> dict[int, int]:
    """Optimal track -> dot assignment, pairs further apart than the track's gate excluded."""
    if not len(predicted) or not len(dots):
        return {}
    cost = np.linalg.norm(predicted[:, None] - dots[None], axis=2)
    cost[~np.isfinite(cost)] = _FAR
    rows, cols = linear_sum_assignment(np.where(cost <= gate[:, None], cost, _FAR))
    return {int(r): int(c) for r, c in zip(rows, cols, strict=True) if cost[r, c] <= gate[r]}


class DotTracker:
    """Keeps dot identities from frame to frame; see the module docstring.

    Parameters
    ----------
    layout : ndarray, shape (M, 2)
        The markers' neutral x, y in millimetres, y up (a marker set's front view).
    max_flow_frames : int
        How many frames optical flow may carry a dot that was not found.
    gate : float, optional
        Largest jump in pixels from the prediction; default 40 % of the closest neutral spacing.
    """

    def __init__(self, layout: np.ndarray, max_flow_frames: int = 3, gate: float | None = None) -> None:
        self.layout = np.asarray(layout, dtype=np.float64) * [1.0, -1.0]  # y down, as images
        self.max_flow_frames = max_flow_frames
        self._gate = gate
        self.mm_per_pixel = float("nan")
        self.origin = np.zeros(2)
        self._pos = np.full((len(layout), 2), np.nan)  # last known position of each track
        self._vel = np.zeros((len(layout), 2))
        self._unseen = np.zeros(len(layout), dtype=int)  # frames since a dot was last found
        self._spacing = self._min_spacing()  # closest neutral distance between two markers, mm
        self._prev_gray: np.ndarray | None = None
        self._prev_image: np.ndarray | None = None
        self._gray: np.ndarray | None = None  # this frame in grey, once flow has needed it

    def start(self, dots: np.ndarray) -> np.ndarray:
        """Give identities to the dots of a neutral frame; returns positions ``(M, 2)``, NaN where none."""
        if len(dots) < 3:
            raise ValueError(f"found {len(dots)} dots; at least 3 are needed to place the layout")
        spread = ((dots - dots.mean(0)) ** 2).sum(1).mean()
        scale = np.sqrt(spread / ((self.layout - self.layout.mean(0)) ** 2).sum(1).mean())
        rot, shift = np.eye(2), dots.mean(0) - scale * self.layout.mean(0)
        match: dict[int, int] = {}
        for _ in range(20):
            predicted = scale * self.layout @ rot.T + shift
            match = _assign(predicted, dots, np.full(len(predicted), 0.6 * self._spacing * scale))
            if len(match) < 3:
                break
            idx = np.array(list(match.items()))
            new = fit_similarity(self.layout[idx[:, 0]], dots[idx[:, 1]])
            if np.allclose(new[0], scale) and np.allclose(new[2], shift, atol=1e-6):
                break
            scale, rot, shift = new
        # Stray blobs of the right colour can always be fitted by a few markers; the layout is
        # there only when most of its markers find a dot where it puts them.
        needed = max(3, math.ceil(MIN_IDENTIFIED * len(self.layout)))
        if len(match) < needed:
            raise ValueError(f"the frame does not show the marker set's layout: only {len(match)} of its "
                             f"{len(self.layout)} markers have a dot where the layout puts them (need {needed}), "
                             f"among {len(dots)} dots found")
        self.mm_per_pixel, self.origin = 1.0 / scale, shift
        self._fit = (scale, rot, shift)
        out = np.full((len(self.layout), 2), np.nan)
        for track, dot in match.items():
            out[track] = dots[dot]
        self._pos = np.where(np.isnan(out), scale * self.layout @ rot.T + shift, out)
        self._unseen = np.where(np.isnan(out[:, 0]), self.max_flow_frames + 1, 0)
        return out

    def step(self, image: np.ndarray, dots: np.ndarray) -> np.ndarray:
        """Follow the tracks into the next frame; returns positions ``(M, 2)``, NaN where unseen."""
        gate_px = self._gate if self._gate is not None else 0.4 * self._spacing / self.mm_per_pixel
        lost = self._unseen > self.max_flow_frames
        predicted = self._pos + np.where(self._unseen[:, None] == 0, self._vel, 0.0)
        if lost.any():
            predicted[lost] = self._layout_guess()[lost]
        gate = np.where(lost, 1.5 * gate_px, gate_px)
        match = _assign(predicted, dots, gate)
        out = np.full_like(self._pos, np.nan)
        for track, dot in match.items():
            out[track] = dots[dot]
        missing = [t for t in range(len(out)) if t not in match and not lost[t]]
        if missing and self._prev_image is not None:
            flowed = self._flow(image, self._pos[missing])
            taken = dots[list(match.values())] if match else np.empty((0, 2))
            for t, p in zip(missing, flowed, strict=True):
                # Flow that lands on a dot another track holds is following that dot (two dots
                # merged, as the lids of a closing eye): the track is lost, not carried.
                on_taken = len(taken) and np.linalg.norm(taken - p, axis=1).min() < 0.5 * gate_px
                if np.isfinite(p).all() and np.linalg.norm(p - predicted[t]) <= gate_px and not on_taken:
                    self._unseen[t] += 1
                    if self._unseen[t] <= self.max_flow_frames:
                        out[t] = p
                        self._vel[t] = p - self._pos[t]
                        self._pos[t] = p
                else:
                    self._unseen[t] = self.max_flow_frames + 1
        found = np.array(list(match), dtype=int)
        if len(found):
            self._vel[found] = np.where(self._unseen[found, None] == 0, out[found] - self._pos[found], 0.0)
            self._pos[found] = out[found]
            self._unseen[found] = 0
        for t in range(len(out)):
            if t not in match and t not in missing:
                self._unseen[t] += 1
        self._prev_image, self._prev_gray, self._gray = image, self._gray, None  # grey converted once per frame
        return out

    def remember(self, image: np.ndarray) -> None:
        """Keep ``image`` as the previous frame for optical flow."""
        self._prev_image, self._prev_gray = image, None

    def _flow(self, image: np.ndarray, points: np.ndarray) -> np.ndarray:
        if self._prev_gray is None:
            if self._prev_image is None:
                raise RuntimeError("optical flow needs a previous frame (call remember first)")
            self._prev_gray = cv2.cvtColor(self._prev_image, cv2.COLOR_BGR2GRAY)
        self._gray = cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)
        start = points.astype(np.float32).reshape(-1, 1, 2)
        # nextPts is only an output buffer here (no OPTFLOW_USE_INITIAL_FLOW). An array type-checks under
        # OpenCV 4.x's stubs and 5.1's alike; None was refused by the first and accepted by the second
        new, status, _ = cv2.calcOpticalFlowPyrLK(self._prev_gray, self._gray, start, start.copy(),
                                                  winSize=(15, 15), maxLevel=2)
        new = new.reshape(-1, 2).astype(np.float64)
        new[status.ravel() == 0] = np.nan
        return new

    def _layout_guess(self) -> np.ndarray:
        """Where the layout, fitted to the tracks seen last frame, puts every marker."""
        seen = self._unseen == 0
        if seen.sum() >= 3:
            self._fit = fit_similarity(self.layout[seen], self._pos[seen])
        scale, rot, shift = self._fit
        return scale * self.layout @ rot.T + shift

    def _min_spacing(self) -> float:
        d = np.linalg.norm(self.layout[:, None] - self.layout[None], axis=2)
        d[np.diag_indices(len(d))] = np.inf
        return float(d.min())


def follow_dots(images: Iterable[np.ndarray], tracker: DotTracker, style: DotStyle = DotStyle(),
                start_frame: int = 0) -> Iterator[np.ndarray]:
    """The tracking loop, one frame at a time: pixel positions ``(M, 2)`` of ``tracker``'s dots in
    each image, NaN where unseen. Identities start on frame ``start_frame`` (a neutral face, where
    :meth:`DotTracker.start` raises ValueError if the layout is not there); earlier frames are NaN.
    Offline tracking (:func:`track_dots`) and a video played live both run this generator.
    """
    started = False
    for index, image in enumerate(images):
        if index < start_frame:
            yield np.full((len(tracker.layout), 2), np.nan)
        elif not started:
            found = tracker.start(find_dots(image, style))
            tracker.remember(image)
            started = True
            yield found
        else:
            yield tracker.step(image, find_dots(image, style))


def track_dots(images: Iterable[np.ndarray], layout: np.ndarray, style: DotStyle = DotStyle(),
               start_frame: int = 0, max_flow_frames: int = 3,
               progress: Callable[[int], None] | None = None) -> tuple[np.ndarray, DotTracker]:
    """Track the dots of ``images`` (:func:`follow_dots` over them all).

    Returns pixel positions ``(frames, M, 2)`` and the tracker (its ``mm_per_pixel`` and
    ``origin`` place the layout in the image).
    """
    tracker = DotTracker(layout, max_flow_frames=max_flow_frames)
    rows: list[np.ndarray] = []
    for pixels in follow_dots(images, tracker, style, start_frame):
        rows.append(pixels)
        if progress:
            progress(1)
    if not rows:
        return np.empty((0, len(layout), 2)), tracker
    return np.stack(rows), tracker


def pixels_to_mm(pixels: np.ndarray, origin: np.ndarray, mm_per_pixel: float) -> np.ndarray:
    """Image positions ``(..., 2)`` (x right, y down) as millimetres ``(..., 3)`` with y up and
    z 0, about ``origin`` (pixels); NaN where the pixel position is."""
    out = np.zeros((*pixels.shape[:-1], 3))
    out[..., 0] = (pixels[..., 0] - origin[0]) * mm_per_pixel
    out[..., 1] = -(pixels[..., 1] - origin[1]) * mm_per_pixel
    out[~np.isfinite(pixels).all(axis=-1)] = np.nan
    return out
