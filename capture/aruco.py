"""ArUco markers from video, with OpenCV contrib's ``ArucoDetector``.

Each marker id is a physical marker, so identity comes from the id itself. A table maps ids to
marker names (``{101: "BROW_L_MED"}``); ids not in the table are named ``aruco_<id>``, or
ignored when the table is given with ``only_table=True``. A marker yields its centre, or its four
corners as ``<name>.c0`` .. ``<name>.c3`` (the library's order: clockwise from top-left of the
printed marker). Where a marker is not seen its points are NaN.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable

import cv2
import numpy as np

DICTIONARIES = {name.removeprefix("DICT_").lower(): getattr(cv2.aruco, name)
                for name in dir(cv2.aruco) if name.startswith("DICT_")}


def make_detector(dictionary: str = "aruco_original", subpixel: bool = True) -> cv2.aruco.ArucoDetector:
    """A detector for one of OpenCV's predefined dictionaries (``aruco_original``, ``4x4_50``, ...)."""
    if dictionary not in DICTIONARIES:
        raise ValueError(f"unknown ArUco dictionary {dictionary!r} (known: {', '.join(sorted(DICTIONARIES))})")
    params = cv2.aruco.DetectorParameters()
    if subpixel:
        params.cornerRefinementMethod = cv2.aruco.CORNER_REFINE_SUBPIX
    return cv2.aruco.ArucoDetector(cv2.aruco.getPredefinedDictionary(DICTIONARIES[dictionary]), params)


def detect(detector: cv2.aruco.ArucoDetector, image: np.ndarray) -> dict[int, np.ndarray]:
    """Markers in one BGR or grey image: id -> corners ``(4, 2)`` in pixels."""
    corners, ids, _ = detector.detectMarkers(image)
    if ids is None:
        return {}
    return {int(i): c.reshape(4, 2).astype(np.float64) for i, c in zip(ids.ravel(), corners, strict=True)}


def track_aruco(images: Iterable[np.ndarray], names: dict[int, str] | None = None, corners: bool = False,
                dictionary: str = "aruco_original", only_table: bool = False,
                progress: Callable[[int], None] | None = None) -> tuple[tuple[str, ...], np.ndarray]:
    """Track ArUco markers through ``images``.

    Returns
    -------
    labels : tuple of str
        Sorted by marker id (and corner).
    pixels : ndarray, shape (frames, len(labels), 2)
        Image coordinates (x right, y down), NaN where unseen.
    """
    detector = make_detector(dictionary)
    per_frame: list[dict[int, np.ndarray]] = []
    for image in images:
        found = detect(detector, image)
        if only_table and names is not None:
            found = {i: c for i, c in found.items() if i in names}
        per_frame.append(found)
        if progress:
            progress(1)
    ids = sorted({i for found in per_frame for i in found})
    base = [(names or {}).get(i, f"aruco_{i}") for i in ids]
    points_per_marker = 4 if corners else 1
    labels = tuple(f"{b}.c{k}" for b in base for k in range(4)) if corners else tuple(base)
    pixels = np.full((len(per_frame), len(ids) * points_per_marker, 2), np.nan)
    for f, found in enumerate(per_frame):
        for m, marker_id in enumerate(ids):
            if marker_id in found:
                c = found[marker_id]
                if corners:
                    pixels[f, 4 * m: 4 * m + 4] = c
                else:
                    pixels[f, m] = c.mean(axis=0)
    return labels, pixels
