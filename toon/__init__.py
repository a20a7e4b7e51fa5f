"""toon: ToonFace faces and motors, turned into drawable geometry without any GL.

Knows faces, CharToon components and the 21 motors, nothing of markers or OpenGL.
"""

from toon.components import Component, PointRef
from toon.expressions import Expression, load_expressions
from toon.face import Face, PolygonSpec, builtin_faces, face_from_dict, load_face, save_face
from toon.motors import (MOTOR_CODES, MOTORS, N_MOTORS, MotorSpec, mirror_values, motor_index,
                         standard_neutral)
from toon.raster import fit_viewbox, rasterize_polygon, render_cpu, to_pixels
from toon.geometry import DrawItem, Geometry
from toon.rig import FaceRig
from toon.svg import geometry_svg, save_svg
from toon.track import MotorTrack
from toon.track_io import load_track, save_track

__all__ = [
    "Component", "DrawItem", "Expression", "Face", "FaceRig", "Geometry", "MOTORS", "MOTOR_CODES", "MotorSpec",
    "MotorTrack", "N_MOTORS", "PointRef", "PolygonSpec", "builtin_faces", "face_from_dict", "fit_viewbox",
    "geometry_svg", "load_expressions", "load_face", "load_track", "mirror_values", "motor_index",
    "rasterize_polygon", "render_cpu", "save_face", "save_svg", "save_track", "standard_neutral", "to_pixels",
]
