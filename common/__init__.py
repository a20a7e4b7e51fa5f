"""Lowest layer shared by every stage: errors, failure values, atomic writes, built-in data.

Nothing here imports any other toonface package; every package may import this one.
"""

from common.arrays import readonly
from common.atomic import atomic_dir, atomic_path, check_folder
from common.data import (
           builtin_names,
           data_path,
           read_document,
           read_versioned,
           resolve_builtin,
           write_document,
           write_toml,
)
from common.errors import InputError, ToonfaceError
from common.failure import Failure

__all__ = ["Failure", "InputError", "ToonfaceError", "atomic_dir", "atomic_path", "builtin_names", "check_folder",
           "data_path", "read_document", "read_versioned", "readonly", "resolve_builtin", "write_document",
           "write_toml"]
