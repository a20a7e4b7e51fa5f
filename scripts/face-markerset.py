"""Write data/markersets/face.toml: the markerless tracker's named points, their neutral the
canonical face model of MediaPipe's Face Landmarker (read from the installed model file).

Run again only if the model or capture.face_landmarks.LANDMARKS change:
``.venv/bin/python scripts/face-markerset.py``.
"""

from pathlib import Path

from capture.face_landmarks import IRIS_EYES, LANDMARKS, canonical_face

MPEG4 = {"NOSE_TIP": "9.3", "BROW_R_MED": "4.2", "BROW_R_CEN": "4.4", "BROW_R_LAT": "4.6", "BROW_L_MED": "4.1",
         "BROW_L_CEN": "4.3", "BROW_L_LAT": "4.5", "LID_R_UP": "3.2", "LID_R_LOW": "3.4", "LID_L_UP": "3.1",
         "LID_L_LOW": "3.3", "EYE_R_IN": "3.8", "EYE_R_OUT": "3.12", "EYE_L_IN": "3.11", "EYE_L_OUT": "3.7",
         "PUPIL_R": "3.6", "PUPIL_L": "3.5", "MOUTH_R": "8.4", "MOUTH_L": "8.3", "LIP_UP": "8.1", "LIP_LOW": "8.2",
         "LIP_UP_IN": "2.2", "LIP_LOW_IN": "2.3", "LIP_UP_R": "8.6", "LIP_UP_L": "8.5", "LIP_LOW_R": "8.8",
         "LIP_LOW_L": "8.7", "CHIN": "2.1", "CHEEK_R": "5.2", "CHEEK_L": "5.1"}
HEAD_REFERENCE = ["FOREHEAD", "FOREHEAD_TOP", "GLABELLA", "NOSE_BRIDGE", "NOSE_RIDGE", "TEMPLE_R", "TEMPLE_L"]

canonical = canonical_face()
lines = [
    "# Written by scripts/face-markerset.py: the points of a markerless face (MediaPipe's Face Landmarker,",
    "# capture/face_landmarks.py), named as toon32 names them where the two agree. Neutral: MediaPipe's",
    "# canonical face model (Apache-2.0), millimetres, x to the face's left, y up, z out of the face; an",
    "# iris centre sits at its eye's contour mean. Head references: forehead, glabella, nose bridge and",
    "# temples, which expressions barely move. The irises are independent: a gaze is not foretold by",
    "# the lids or the lips, so a gap is filled from the other iris, or straight across (a blink).",
    'format = "toonface.markerset/1"',
    'name = "face"',
    'description = "markerless face: MediaPipe Face Landmarker points, brows, lids, eye corners, irises, lips, '
    'jaw, rigid forehead and nose references"',
    f"head_reference = {HEAD_REFERENCE!r}".replace("'", '"'),
    'independent = ["PUPIL_R", "PUPIL_L"]',
    "",
    "[markers]",
]
for name, index in LANDMARKS.items():
    point = canonical[list(IRIS_EYES[index])].mean(axis=0) if index in IRIS_EYES else canonical[index]
    x, y, z = (round(float(v), 2) for v in point)
    extra = f', mpeg4 = "{MPEG4[name]}"' if name in MPEG4 else ""
    lines.append(f"{name:<12} = {{ neutral = [{x}, {y}, {z}]{extra} }}  # landmark {index}")
out = Path(__file__).resolve().parents[1] / "data" / "markersets" / "face.toml"
out.write_text("\n".join(lines) + "\n")
print(f"wrote {out}")
