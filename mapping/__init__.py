"""mapping: turn a :class:`capture.Take` into a :class:`toon.MotorTrack`.

Clean (spikes, gaps, smoothing) with head motion removed, calibrate a performer profile, map
per channel by a mapping file. Imports ``capture`` (for takes) and ``toon`` (for motor codes
and tracks), nothing else.
"""

from mapping.clean import CleanReport, CleanSettings, clean_stabilised, clean_take
from mapping.mapfile import Mapping, MotorRule, load_mapping, parse_mapping
from mapping.mapper import map_stabilised
from mapping.profile import Profile, SourceRange, load_profile, save_profile
from mapping.stabilise import Stabilised, stabilise
from mapping.workflow import Prepared, calibrate, choose_mapping, map_take, prepare

__all__ = ["CleanReport", "CleanSettings", "Mapping", "MotorRule", "Prepared", "Profile", "SourceRange", "Stabilised",
           "calibrate", "choose_mapping", "clean_stabilised", "clean_take", "load_mapping", "load_profile",
           "map_stabilised", "map_take", "parse_mapping", "prepare", "save_profile", "stabilise"]
