"""The Animator's command language: one line per command, one line of reply.

::

    ELU 0 500 ERU 0 500      move motors: code, target 0..1, milliseconds (repeat for several);
                             a face's parameters beyond the 21 too (HT 0.8 300 tilts the head)
    frame V1 ... V21 [MS]    set all 21 motors, in ToonFace order (over MS milliseconds)
    play NAME [MS]           a standard motion or expression (smile, blink, nod, happiness, ...)
    hold CODE VALUE [...]    override motors over everything else until released
    release [CODE ...]       let them go (all, without codes)
    state                    the 21 current values, and which provider moves each
                             (idle, tracking, motions or manual), then the parameters
    motions                  the names play accepts
    help                     this list

Every line gets exactly one reply, ``ok ...`` or ``error: ...``; a malformed line changes nothing
(it is parsed whole before anything moves). Codes are case-insensitive.
"""

from __future__ import annotations

import math

import numpy as np

from player.animator import Animator, Move, moves_to, schedule
from player.motions import motion_names, standard_motion
from player.providers import Mixer
from toon import MOTOR_CODES, Expression

MAX_MS = 600_000  # ten minutes
HELP = ("commands: CODE TARGET MS [...] | frame V1..V21 [MS] | play NAME [MS] | hold CODE VALUE [...] | "
        "release [CODE ...] | state | motions | help")


class CommandError(ValueError):
    """A line that cannot be carried out; its text is the reply after ``error: ``."""


class Commands:
    """Parses and carries out command lines on an :class:`Animator`.

    Parameters
    ----------
    animator : Animator
    neutral : ndarray, shape (21,)
        The face's rest pose (for motions that come back to it).
    expressions : dict
        The repertoire ``play`` can use.
    clock : callable
        The loop's time (seconds since it started), so motions are scheduled on its timeline.
    mixer : Mixer, optional
        The providers the face's values come from: ``state`` reports what it shows and who
        moves each motor, ``hold`` and ``release`` set its overrides.
    extras : Animator, optional
        Moves the face's parameters beyond the 21 (its ``codes``): a move names them as it
        names motors.
    """

    def __init__(self, animator: Animator, neutral: np.ndarray, expressions: dict[str, Expression],
                 clock, mixer: Mixer | None = None, extras: Animator | None = None) -> None:
        self.animator, self.neutral, self.expressions, self.clock = animator, neutral, expressions, clock
        self.mixer = mixer
        self.extras = extras
        self.rests = {} if extras is None else dict(zip(extras.codes, extras.values().tolist(), strict=True))
        self.movable = (*MOTOR_CODES, *(extras.codes if extras is not None else ()))

    def handle(self, line: str) -> str:
        """Carry out one line; returns its reply (never raises for bad input)."""
        try:
            return "ok" + (f" {text}" if (text := self._run(line.strip())) else "")
        except CommandError as exc:
            return f"error: {exc}"

    def _run(self, line: str) -> str:
        words = line.split()
        if not words:
            raise CommandError("empty line (try: help)")
        head = words[0].lower()
        if head == "help":
            return HELP
        if head == "state":
            return self._state()
        if head in ("hold", "release"):
            return self._override(head, words[1:])
        if head == "motions":
            return " ".join(motion_names(self.expressions))
        if head == "frame":
            return self._frame(words[1:])
        if head == "play":
            return self._play(words[1:])
        return self._moves(words)

    def _state(self) -> str:
        more = "" if self.extras is None else " " + " ".join(
            f"{c}={v:.3f}" for c, v in zip(self.extras.codes, self.extras.values(), strict=True))
        if self.mixer is None:
            return " ".join(f"{c}={v:.3f}" for c, v in zip(MOTOR_CODES, self.animator.values(), strict=True)) + more
        values = " ".join(f"{c}={v:.3f}" for c, v in zip(MOTOR_CODES, self.mixer.shown, strict=True))
        who = self.mixer.who()
        groups = {name: [c for c, w in zip(MOTOR_CODES, who, strict=True) if w == name] for name in dict.fromkeys(who)}
        return f"{values} by " + " ".join(f"{name}={','.join(codes)}" for name, codes in groups.items()) + more

    def _override(self, head: str, words: list[str]) -> str:
        if self.mixer is None:
            raise CommandError(f"{head}: this player has no overrides")
        if head == "release":
            codes = [self._code(w) for w in words] or None
            self.mixer.release(codes)
            return f"released {len(codes) if codes else 'all'}"
        if not words or len(words) % 2:
            raise CommandError("hold needs CODE VALUE pairs")
        targets = {self._code(words[k]): _number(words[k + 1], "value", 0.0, 1.0) for k in range(0, len(words), 2)}
        if len(targets) != len(words) // 2:
            raise CommandError("a motor is named twice; give each motor one value per command")
        self.mixer.hold(targets)
        return f"holding {len(targets)}"

    @staticmethod
    def _code(word: str) -> str:
        if word.upper() not in MOTOR_CODES:
            raise CommandError(f"unknown motor {word!r} (motors: {' '.join(MOTOR_CODES)})")
        return word.upper()

    def _moves(self, words: list[str]) -> str:
        if words[0].upper() not in self.movable and not (len(words) % 3 == 0 and _is_number(words[1])):
            raise CommandError(f"{words[0]!r} is not a command; {HELP}")  # such as quit: not a move either
        if len(words) % 3:
            raise CommandError(f"expected CODE TARGET MS triples, got {len(words)} words")
        moves: list[Move] = []
        for k in range(0, len(words), 3):
            code = words[k].upper()
            if code not in self.movable:
                extra = f"; parameters: {' '.join(self.movable[len(MOTOR_CODES):])}" if self.extras else ""
                raise CommandError(f"unknown motor {words[k]!r} (motors: {' '.join(MOTOR_CODES)}{extra})")
            if any(m.code == code for m in moves):  # "ELU 0 500 ELU 1 500" answered "moving 2"
                raise CommandError(f"{code} is named twice; give each motor one target per command")
            moves.append(Move(code, _number(words[k + 1], "target", 0.0, 1.0), _ms(words[k + 2])))
        motors = [m for m in moves if m.code in MOTOR_CODES]
        if motors or self.extras is None:
            self.animator.command(motors)
        if self.extras is not None and len(motors) < len(moves):
            self.extras.command([m for m in moves if m.code not in MOTOR_CODES])
        return f"moving {len(moves)}"

    def _frame(self, words: list[str]) -> str:
        if len(words) not in (21, 22):
            raise CommandError(f"frame needs 21 values (and optionally MS), got {len(words)}")
        values = np.array([_number(w, f"value {i + 1}", 0.0, 1.0) for i, w in enumerate(words[:21])])
        seconds = _ms(words[21]) if len(words) == 22 else 0.0
        self.animator.command(moves_to(values, seconds))
        return "frame"

    def _play(self, words: list[str]) -> str:
        if len(words) not in (1, 2):
            raise CommandError("play needs NAME [MS]")
        name = words[0].lower()
        seconds = _ms(words[1]) if len(words) == 2 else None
        try:
            motion = standard_motion(name, seconds, self.animator.values(), self.neutral, self.expressions,
                                     self.rests)
        except KeyError:
            raise CommandError(f"unknown motion {words[0]!r} (try: motions)") from None
        now = self.clock()
        for offset, moves in motion.steps:
            schedule((self.animator, *([self.extras] if self.extras else [])), now + offset, moves)
        return f"playing {name}"


def _is_number(word: str) -> bool:
    try:
        float(word)
    except ValueError:
        return False
    return True


def _number(word: str, what: str, low: float, high: float) -> float:
    try:
        value = float(word)
    except ValueError:
        raise CommandError(f"{what}: expected a number, got {word!r}") from None
    if not (math.isfinite(value) and low <= value <= high):
        raise CommandError(f"{what}: must be {low:g}..{high:g}, got {word}")
    return value


def _ms(word: str) -> float:
    return _number(word, "milliseconds", 0.0, MAX_MS) / 1000.0
