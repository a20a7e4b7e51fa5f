"""The frame solve (mapping.solver_frames) against a plain per-frame least-squares oracle: the
blocks it splits the motors into, and shares equal to the whole system's, however many frames."""

import numpy as np
import pytest

from mapping.solver_frames import FEW, REACH, RIDGE, Layout, _spd_solve, blocks, solve_frames


def _bases(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Five motors over seven markers: motors 0 and 1 share marker 1; motor 3 moves markers 3 and
    4, and motor 4 marker 5 and, on its low side only, marker 4 (linked to 3 through one side);
    motor 2 moves marker 2 alone; no motor moves marker 6."""
    up, down = np.zeros((5, 7, 3)), np.zeros((5, 7, 3))
    for motor, markers in ((0, (0, 1)), (1, (1,)), (2, (2,)), (3, (3, 4)), (4, (5,))):
        up[motor, list(markers)] = rng.normal(0.0, 2.0, (len(markers), 3))
        down[motor, list(markers)] = rng.normal(0.0, 2.0, (len(markers), 3))
    down[4, 4] = rng.normal(0.0, 2.0, 3)
    return up, down


def test_motors_that_share_no_marker_on_either_side_are_solved_apart():
    up, down = _bases(np.random.default_rng(1))
    groups = blocks(up, down)
    assert [g.tolist() for g in groups] == [[[2]], [[0, 1], [3, 4]]]
    assert Layout.of(up, down).used.tolist() == [True] * 6 + [False]


def _oracle(up: np.ndarray, down: np.ndarray, d: np.ndarray, weight: np.ndarray) -> np.ndarray:
    """Each frame on its own, as the module says: a ridge solve with the sides' mean, then one with
    each motor's basis of the side the first put it on (no robust passes)."""
    k = len(up)
    mean = (up + down) / 2  # a share s moves a marker by s * up above rest, s * down below
    ridge = RIDGE * float(np.mean((np.concatenate([up, down]) ** 2).sum(axis=(1, 2))))
    out = np.empty((len(d), k))
    for f in range(len(d)):
        w = np.repeat(weight[f], 3)
        basis = mean.reshape(k, -1).T  # (3M, K)
        for _ in range(2):
            gram = basis.T @ (w[:, None] * basis) + ridge * np.eye(k)
            s = np.clip(np.linalg.solve(gram, basis.T @ (w * d[f].ravel())), -REACH, REACH)
            basis = np.where(s >= 0, up.reshape(k, -1).T, down.reshape(k, -1).T)
        out[f] = s
    return out


@pytest.mark.parametrize("frames", [1, FEW - 1, FEW, 300])
def test_the_shares_are_the_whole_systems_one_frame_at_a_time(frames):
    rng = np.random.default_rng(62)
    up, down = _bases(rng)
    truth = rng.uniform(-1.0, 1.0, (frames, 5))
    d = np.einsum("fk,kmc->fmc", np.maximum(truth, 0), up) + np.einsum("fk,kmc->fmc", np.minimum(truth, 0), down)
    d += rng.normal(0.0, 0.05, d.shape)
    weight = (rng.uniform(size=(frames, 7)) > 0.15).astype(float)
    weight[:, 6] = 1.0
    layout = Layout.of(up, down)
    shares, _ = solve_frames(layout, 0.1, d[:, layout.used], weight[:, layout.used], robust=False)
    np.testing.assert_allclose(shares, _oracle(up, down, d, weight), atol=1e-9)


@pytest.mark.parametrize("truth", [1.0, 0.5, -0.5, -1.0])
def test_a_motor_that_moves_further_below_rest_than_above_is_solved_on_its_side(truth):
    """An upper lid opens 4 mm and closes 6 (a share moves its marker by share * up above rest,
    share * down below). The first pass solved with half the sides' difference, not their mean,
    put an opening below rest, and the pass after solved it with the closing's basis: 1.0 read
    0.67 (the sweep's residual, which scales the robust weights, is solved so). What is left is
    the ridge's pull towards rest."""
    up, down = np.array([[[0.0, 4.0, 0.0]]]), np.array([[[0.0, 6.0, 0.0]]])
    d = (truth * (up if truth >= 0 else down))[:, 0][None]  # (1 frame, 1 marker, 3)
    layout = Layout.of(up, down)
    shares, _ = solve_frames(layout, 0.1, d, np.ones((1, 1)), robust=False)
    energy = 16.0 if truth >= 0 else 36.0
    assert layout.ridge == pytest.approx(RIDGE * 26.0)
    assert shares[0, 0] == pytest.approx(truth * energy / (energy + layout.ridge), abs=1e-9)


def test_many_small_systems_solve_as_lapack_solves_them():
    rng = np.random.default_rng(3)
    m = rng.normal(size=(400, 2, 5, 5))
    a = m @ np.swapaxes(m, -1, -2) + 0.01 * np.eye(5)
    y = rng.normal(size=(400, 2, 5))
    np.testing.assert_allclose(_spd_solve(a, y), np.linalg.solve(a, y[..., None])[..., 0], rtol=1e-8, atol=1e-8)
