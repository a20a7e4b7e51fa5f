"""Type stub: the names the package loads lazily on first use (``lazy_loader``)."""

from .components import Component, PointRef
from .expressions import Expression, load_expressions
from .face import Face, PolygonSpec, builtin_faces, face_from_dict, load_face, save_face
from .geometry import DrawItem, Geometry
from .motors import (
    MOTOR_CODES,
    MOTORS,
    N_MOTORS,
    MotorSpec,
    mirror_values,
    motor_index,
    standard_neutral,
)
from .raster import fit_viewbox, rasterize_polygon, render_cpu, to_pixels
from .rig import FaceRig
from .svg import geometry_svg, save_svg
from .track import MotorTrack
from .track_io import load_track, save_track

__all__ = [
    "Component",
    "DrawItem",
    "Expression",
    "Face",
    "FaceRig",
    "Geometry",
    "MOTORS",
    "MOTOR_CODES",
    "MotorSpec",
    "MotorTrack",
    "N_MOTORS",
    "PointRef",
    "PolygonSpec",
    "builtin_faces",
    "face_from_dict",
    "fit_viewbox",
    "geometry_svg",
    "load_expressions",
    "load_face",
    "load_track",
    "mirror_values",
    "motor_index",
    "rasterize_polygon",
    "render_cpu",
    "save_face",
    "save_svg",
    "save_track",
    "standard_neutral",
    "to_pixels",
]
