"""The bridge across a lost head reference (mapping.reference_bridge): toon32's references on a
turning head, one lost for a while; a point on the chin, carried by each pose, says how far the
bridged pose sits from the truth."""

import numpy as np
import pytest

from capture import load_markerset
from capture.synthetic import rotation_yaw_pitch
from mapping.reference_bridge import bridge_edge, bridge_references, fade_frames
from mapping.stabilise import robust_rigid_fit

CHIN = np.array([0.0, -80.0, 20.0])


def _references() -> tuple[list[str], np.ndarray]:
    """toon32's head references and their shape ``(K, 3)``."""
    ms = load_markerset("toon32")
    return list(ms.head_reference), ms.neutral[[ms.labels.index(r) for r in ms.head_reference]]


def _turning(frames: int, rate: float) -> tuple[np.ndarray, np.ndarray]:
    """A head turning and nodding as it drifts: rotation ``(F, 3, 3)`` and translation ``(F, 3)``."""
    t = np.arange(frames) / rate
    rotation = rotation_yaw_pitch(np.radians(20 * np.sin(0.5 * t)), np.radians(10 * np.sin(0.3 * t)))
    return rotation, np.column_stack([30 * np.sin(0.2 * t), 5 * t, np.zeros_like(t)])


def _chin(rotation: np.ndarray, translation: np.ndarray) -> np.ndarray:
    """Where each pose puts the chin, ``(F, 3)``."""
    return np.einsum("fij,j->fi", rotation, CHIN) + translation


def _skin(seed: int = 4):
    """toon32's head references on a turning head, each drifting off the skull by a smooth
    0.6 mm of its own (real references are skin, not bone); the true pose, and the references."""
    _, shape = _references()
    rotation, translation = _turning(600, 60.0)
    t = np.arange(600) / 60.0
    rng = np.random.default_rng(seed)
    drift = 0.6 * np.sin(2 * np.pi * rng.uniform(0.2, 0.6, (1, len(shape), 3)) * t[:, None, None]
                         + rng.uniform(0, 6, (1, len(shape), 3)))
    world = np.einsum("fij,fkj->fki", rotation, shape + drift) + translation[:, None, :]
    return shape, world


def test_a_lost_head_reference_does_not_make_the_head_jump():
    """Fitted on four of five references the head sits off the fit on all five (they drift
    apart); over a 0.5 s loss the pose is bridged from the fits either side, so a point on the
    chin stays within a quarter of that jump of where the full fit puts it (on the AnimFace jaw
    take the markers' shift falls from 0.28 to 0.07 mm)."""
    shape, world = _skin()
    full_rot, full_trans, ok = robust_rigid_fit(shape, world)
    cut = world.copy()
    cut[300:330, 2] = np.nan
    rot, trans, _ = robust_rigid_fit(shape, cut)
    bridged_rot, bridged_trans = bridge_references(cut, shape, rot, trans, ok)
    full = _chin(full_rot, full_trans)
    jump = np.linalg.norm(_chin(rot, trans) - full, axis=1)[300:330].max()
    left = np.linalg.norm(_chin(bridged_rot, bridged_trans) - full, axis=1)[300:330].max()
    assert jump > 0.1 and left < 0.25 * jump, (jump, left)
    np.testing.assert_array_equal(bridged_rot[:300], rot[:300])


def test_a_lost_head_reference_carries_no_single_frames_jitter_across_its_gap():
    """Rigid references with 0.3 mm of jitter, one temple lost for 0.5 s every 2 s: the
    difference between the fits on all and on four references was read from the one frame
    either side, so each stretch kept that frame's jitter (a point on the chin 0.20 mm off on
    average over a stretch, RMS over the stretches); averaged over the frames that hold steady
    near it, 0.09 mm, against 0.08 mm for the fit on four references alone (right here, where
    the references are rigid)."""
    names, shape = _references()
    rotation, translation = _turning(3600, 60.0)
    rng = np.random.default_rng(1)
    world = np.einsum("fij,kj->fki", rotation, shape) + translation[:, None, :]
    world += rng.normal(0.0, 0.3, world.shape)
    starts = np.arange(60, 3500, 120)
    for start in starts:
        world[start:start + 30, names.index("TEMPLE_R")] = np.nan
    rot, trans, ok = robust_rigid_fit(shape, world)
    bridged_rot, bridged_trans = bridge_references(world, shape, rot, trans, ok, bridge_edge(60.0))
    error = _chin(bridged_rot, bridged_trans) - _chin(rotation, translation)
    bias = np.array([np.linalg.norm(error[start:start + 30].mean(axis=0)) for start in starts])
    assert np.sqrt(np.mean(bias ** 2)) < 0.13, bias


def test_a_slide_read_at_a_lost_references_edge_fades_into_its_stretch():
    """The forehead slides 2 mm up (raised brows) until a third of a second into a 2 s stretch
    where a temple is lost, then the face rests. Where it rests, the fit on the references still
    seen is right; the bridge carried the edge's difference (read while the forehead slid, a
    point on the chin 0.33 mm off there) straight across, and the chin sat 0.10-0.17 mm off
    where the face rests. Faded over a quarter second (30 frames), it is carried near the edge
    alone: 0.008 mm at most where the face rests."""
    names, shape = _references()
    rotation, translation = _turning(960, 120.0)
    local = np.tile(shape, (960, 1, 1))
    local[300:400, names.index("FOREHEAD"), 1] += 2.0  # slid up, until 40 frames in
    world = np.einsum("fij,fkj->fki", rotation, local) + translation[:, None, :]
    world[360:600, names.index("TEMPLE_R")] = np.nan
    rot, trans, ok = robust_rigid_fit(shape, world)

    def chin_error(fade: float) -> np.ndarray:
        bridged = bridge_references(world, shape, rot, trans, ok, bridge_edge(120.0), fade)
        return np.linalg.norm(_chin(*bridged) - _chin(rotation, translation), axis=1)

    carried, faded = chin_error(np.inf), chin_error(fade_frames(120.0))
    assert carried[450:510].mean() > 0.1, carried[450:510].mean()  # the old bridge, for scale
    assert faded[450:510].max() < 0.02, faded[450:510].max()
    assert faded[362] == pytest.approx(carried[362], rel=0.1)  # near the edge, what was read there holds


def test_a_reference_lost_for_a_frame_inside_a_longer_loss_does_not_bring_back_its_edge():
    """As above, and the nose tip lost for one frame (a spike taken out) where the face rests,
    halfway through the temple's loss. That splits the stretch in three; each part bridged from
    its own edges carried the first edge's slide at full weight again beside the lost frame (a
    point on the chin 0.26 mm off); bridged from the edges of the whole loss, it stays faded."""
    names, shape = _references()
    rotation, translation = _turning(960, 120.0)
    local = np.tile(shape, (960, 1, 1))
    local[300:400, names.index("FOREHEAD"), 1] += 2.0
    world = np.einsum("fij,fkj->fki", rotation, local) + translation[:, None, :]
    world[360:600, names.index("TEMPLE_R")] = np.nan
    world[480, names.index("NOSE_TIP")] = np.nan
    rot, trans, ok = robust_rigid_fit(shape, world)
    bridged = bridge_references(world, shape, rot, trans, ok, bridge_edge(120.0), fade_frames(120.0))
    error = np.linalg.norm(_chin(*bridged) - _chin(rotation, translation), axis=1)
    assert error[450:510].max() < 0.02, error[450:510].max()
    assert error[362] > 0.1  # near the loss's own edge, the slide read there is carried as before
