"""A falsy value that says why an estimate could not be made (after skimage's FailedEstimation)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal


@dataclass(frozen=True)
class Failure:
    """The result of an estimation that could not be made.

    Estimators return either their result or a ``Failure``; test the value with ``if not result``.

    Examples
    --------
    >>> f = Failure("head markers missing in every frame of 0.0-1.0 s")
    >>> bool(f), str(f)
    (False, 'head markers missing in every frame of 0.0-1.0 s')
    """

    reason: str

    def __bool__(self) -> Literal[False]:  # so that type checkers narrow `if not result`
        return False

    def __str__(self) -> str:
        return self.reason
