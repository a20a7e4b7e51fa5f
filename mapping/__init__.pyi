"""Type stub: the names the package loads lazily on first use (``lazy_loader``)."""

from .clean import CleanReport, clean_stabilised, clean_take
from .mapfile import Mapping, MotorRule, load_mapping, parse_mapping
from .mapper import map_stabilised
from .profile import Profile, SourceRange, load_profile, save_profile
from .settings import CleanSettings
from .stabilise import Stabilised, stabilise
from .workflow import Prepared, calibrate, choose_mapping, map_take, prepare

__all__ = [
    "CleanReport",
    "CleanSettings",
    "Mapping",
    "MotorRule",
    "Prepared",
    "Profile",
    "SourceRange",
    "Stabilised",
    "calibrate",
    "choose_mapping",
    "clean_stabilised",
    "clean_take",
    "load_mapping",
    "load_profile",
    "map_stabilised",
    "map_take",
    "parse_mapping",
    "prepare",
    "save_profile",
    "stabilise",
]
