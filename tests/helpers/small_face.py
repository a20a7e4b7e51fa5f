"""A small face whose motors are known exactly, for the sweep-taught solver's tests
(``tests/mapping/test_solver*.py``): a linear face, each motor moving its markers by a known
amount per unit of share on each side of rest, a smile that lifts the lower lid, a mirror pair of
brows that lift the nose between them."""

import numpy as np

MARKERS = {"BROW_R": (-30, 40, 0), "BROW_L": (30, 40, 0), "LID_R": (-30, 10, 0), "NOSE": (0, 0, 20),
           "MOUTH_R": (-25, -40, 0), "MOUTH_L": (25, -40, 0), "LIP_LOW": (0, -45, 5), "CHIN": (0, -70, 0)}
CODES = ("BR", "BL", "ER", "MR", "MB")
OWN = (("BROW_R",), ("BROW_L",), ("LID_R",), ("MOUTH_R",), ("CHIN", "LIP_LOW"))
READ = ((0, 1), (1, 1), (2, 1), (4, 0), (7, 1))  # the marker and axis each motor's rule reads
COLUMNS = {name: i for i, name in enumerate(MARKERS)}
REST = np.array(list(MARKERS.values()), float)


def motor_bases() -> tuple[np.ndarray, np.ndarray]:
    """Each motor's displacement per unit of share, ``(K, M, 3)``, above and below rest."""
    up = np.zeros((len(CODES), len(MARKERS), 3))
    down = np.zeros_like(up)

    def put(code: str, marker: str, high: tuple, low: tuple) -> None:
        up[CODES.index(code), COLUMNS[marker]] = high
        down[CODES.index(code), COLUMNS[marker]] = low

    put("BR", "BROW_R", (0, 8, 0), (0, 6, 0))  # raised 8 mm, lowered 6
    put("BL", "BROW_L", (0, 8, 0), (0, 6, 0))
    put("BR", "NOSE", (0, 1, 0), (0, 1, 0))  # the brows between them lift the nose by 2 mm
    put("BL", "NOSE", (0, 1, 0), (0, 1, 0))
    put("ER", "LID_R", (0, 3, 0), (0, 1, 0))  # a lower lid: 3 mm up, 1 down
    put("MR", "MOUTH_R", (-6, 4, 0), (-4, 1, 0))  # a smile out and up; a pucker in and down
    put("MR", "LID_R", (0, 1.5, 0), (0, 0, 0))  # a smile lifts the lower lid
    put("MB", "CHIN", (0, -8, -2), (0, -1, 0))
    put("MB", "LIP_LOW", (0, -8, -1), (0, -1, 0))
    put("MB", "MOUTH_R", (0, -5, 0), (0, 0, 0))
    put("MB", "MOUTH_L", (0, -5, 0), (0, 0, 0))
    return up, down


def face(shares: np.ndarray, bases: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
    """Head-frame markers ``(F, M, 3)`` for motor shares ``(F, K)`` (``bases``: :func:`motor_bases`'s by default)."""
    up, down = bases or motor_bases()
    moved = np.where(shares[..., None, None] >= 0, up, down) * shares[..., None, None]
    return REST + moved.sum(axis=1)


def sweep() -> np.ndarray:
    """Shares ``(F, K)`` of a range-of-motion sweep: each group (the brows together) to its low
    end, held, to its high end, held, and back."""
    one = np.concatenate([np.linspace(0, -1, 10), np.full(10, -1.0), np.linspace(-1, 1, 20), np.full(10, 1.0),
                          np.linspace(1, 0, 10)])
    groups = (("BR", "BL"), ("ER",), ("MR",), ("MB",))
    shares = np.zeros((len(one) * len(groups), len(CODES)))
    for g, group in enumerate(groups):
        for code in group:
            shares[g * len(one):(g + 1) * len(one), CODES.index(code)] = one
    return shares


def rule_reading(local: np.ndarray, bases: tuple[np.ndarray, np.ndarray] | None = None) -> np.ndarray:
    """What per-marker rules read: each motor from one coordinate of its own marker, as a share of
    the sweep's range of it on that side (a profile's ranges): the lid reads a smile's lift as
    its own raise."""
    up, _ = bases or motor_bases()
    swept = face(sweep(), bases)
    out = np.empty((len(local), len(CODES)))
    for k, (m, axis) in enumerate(READ):
        sign = np.sign(up[k, m, axis])
        value, extent = sign * (local[:, m, axis] - REST[m, axis]), sign * (swept[:, m, axis] - REST[m, axis])
        out[:, k] = np.where(value >= 0, value / extent.max(), -value / extent.min())
    return out
