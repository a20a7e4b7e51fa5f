"""Undo and redo for the studio's editors: the states an editor left, and those it undid."""

from __future__ import annotations

from typing import Generic, TypeVar

State = TypeVar("State")


class History(Generic[State]):
    """Up to ``levels`` earlier states to go back to, and the undone ones to go forward to again
    (a new edit drops those)."""

    def __init__(self, levels: int) -> None:
        self.levels = levels
        self._back: list[State] = []
        self._forward: list[State] = []

    def push(self, left: State) -> None:
        """An edit left ``left``."""
        self._back = [*self._back[-(self.levels - 1):], left]
        self._forward.clear()

    def undo(self, current: State) -> State | None:
        """The state before ``current``, or None where there is none."""
        if not self._back:
            return None
        self._forward.append(current)
        return self._back.pop()

    def redo(self, current: State) -> State | None:
        """The state ``current`` was undone from, or None where there is none."""
        if not self._forward:
            return None
        self._back.append(current)
        return self._forward.pop()

    def clear(self) -> None:
        self._back.clear()
        self._forward.clear()

    def counts(self) -> dict[str, int]:
        """How many edits can be undone and redone: ``{"undo": n, "redo": m}``."""
        return {"undo": len(self._back), "redo": len(self._forward)}
