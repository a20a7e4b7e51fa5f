"""Head stabilisation: robust rigid fits, the head frame, and cleaning in it."""

import numpy as np
import pytest
from scipy.interpolate import CubicSpline

from capture import Take, load_markerset, synthesize
from capture.markerset import find_markerset
from capture.performance import default_performance
from capture.synthetic import rotation_yaw_pitch
from mapping.clean import CleanSettings, clean_stabilised, clean_take
from mapping.stabilise import rigid_fit, robust_rigid_fit, stabilise, yaw_pitch_degrees
from toon import MOTOR_CODES


def _unseen(target):
    target[1, 0] = np.nan  # one unseen marker still leaves 4


def _spike(target):
    target[0, 2] += [0.0, 30.0, 0.0]  # one head marker jumps in frame 0


@pytest.mark.parametrize("fit, fault, atol", [(rigid_fit, _unseen, 1e-9), (robust_rigid_fit, _spike, 1e-6)],
                         ids=["plain-with-unseen", "robust-with-spike"])
def test_fits_recover_a_known_rotation(fit, fault, atol):
    rng = np.random.default_rng(0)
    source = rng.normal(0, 50, (5, 3))
    rot = rotation_yaw_pitch(np.radians(np.array([20.0, -10.0])), np.radians(np.array([5.0, 12.0])))
    target = np.einsum("fij,kj->fki", rot, source) + np.array([[1.0, 2.0, 3.0], [-4, 0, 9]])[:, None]
    fault(target)
    fitted, _, ok = fit(source, target)
    assert ok.all()
    np.testing.assert_allclose(fitted, rot, atol=1e-9)
    yaw, pitch = yaw_pitch_degrees(fitted)
    np.testing.assert_allclose(yaw, [20.0, -10.0], atol=atol)
    np.testing.assert_allclose(pitch, [5.0, 12.0], atol=atol)


def test_a_spike_the_fit_on_all_shares_out_is_judged_against_the_others():
    """toon32's seven references, one (the temple) 5 mm off in the last frame before its gap,
    where no spike test can judge it: the fit on all shares its miss out (2.4 mm on the temple
    on a third-performer draw, under the 3 mm tolerance) and turned the head by degrees; judged
    against the fit on the other six it misses by 5 mm and is left out."""
    markerset = load_markerset("toon32")
    source = markerset.neutral[[markerset.labels.index(r) for r in markerset.head_reference]]
    rot = rotation_yaw_pitch(np.radians(np.array([20.0])), np.radians(np.array([5.0])))
    target = np.einsum("fij,kj->fki", rot, source)
    target[0, markerset.head_reference.index("TEMPLE_R")] += [0.0, 3.0, 4.0]  # 5 mm
    plain, _, _ = rigid_fit(source, target)
    robust, _, ok = robust_rigid_fit(source, target)
    def turned(r):
        return np.degrees(np.arccos(np.clip((np.trace(r[0].T @ rot[0]) - 1) / 2, -1, 1)))
    assert turned(plain) > 0.5  # the miss shared out: under the tolerance on every reference
    assert ok.all() and turned(robust) < 1e-6


def test_head_frame_positions_are_the_face_motion_without_the_turns():
    syn = synthesize(rate=60.0, noise_mm=0.0, performance=default_performance(6, max_turn_deg=30))
    still = synthesize(rate=60.0, noise_mm=0.0, performance=default_performance(6, max_turn_deg=0))
    ms = load_markerset("toon32")
    rows = [syn.take.index(r) for r in ms.head_reference]
    result = stabilise(syn.take.positions, rows, np.array([ms.neutral_of(r) for r in ms.head_reference]))
    assert result.ok.all()
    # the still performer's world positions are its head frame plus the sway (translation only)
    sway = still.take.positions[:,
                                rows].mean(axis=1) - ms.neutral[[ms.labels.index(r) for r in ms.head_reference]].mean(0)
    still_local = still.take.positions - sway[:, None, :]
    face = [syn.take.index(m) for m in ("BROW_R_CEN", "LID_L_UP", "LIP_LOW", "MOUTH_R")]
    np.testing.assert_allclose(result.local[:, face], still_local[:, face], atol=1e-6)
    np.testing.assert_allclose(result.world(), syn.take.positions, atol=1e-9)


def test_cleaning_in_the_head_frame_rejects_spikes_not_fast_turns():
    syn = synthesize(rate=60.0, noise_mm=0.2, performance=default_performance(8, max_turn_deg=30), seed=3)
    pos = syn.take.positions.copy()
    pos[200, syn.take.index("NOSE_TIP")] += [0.0, 0.0, 15.0]  # a head reference spikes
    pos[300, syn.take.index("LID_R_UP")] += [15.0, 0.0, 0.0]
    take = Take(pos, syn.take.labels, 60.0)
    cleaned, report = clean_stabilised(take, load_markerset("toon32"))
    assert report.rejected == 2 and report.filled == 2 and report.no_head_frames == 0
    # no trace of the spikes in the head frame: the lid follows its clean path within jitter
    lid = syn.take.index("LID_R_UP")
    truth = clean_stabilised(syn.take, load_markerset("toon32"))[0].local[:, lid]
    assert np.abs(cleaned.local[290:310, lid] - truth[290:310]).max() < 0.5


def test_clean_take_head_frame_output_and_fallback_without_a_marker_set():
    syn = synthesize(seconds=3, rate=60.0, noise_mm=0.1)
    head, report = clean_take(syn.take, head_frame=True)
    assert report.head == "removed" and len(head.meta["head"]["yaw_deg"]) == syn.take.frames
    assert abs(np.nanmean(head.positions[:, head.index("FOREHEAD")] - [0.0, 55.0, 8.0])) < 0.2
    odd = Take(syn.take.positions, tuple(f"M{i}" for i in range(syn.take.markers)), 60.0)
    assert find_markerset(odd.labels) is None
    world, report = clean_take(odd, CleanSettings())
    assert report.head.startswith("left in") and np.allclose(world.positions, syn.take.positions, atol=1.0)


@pytest.mark.parametrize("name", ["toon32", "animface41", "gluedots16"])
def test_find_markerset_recognises_each_builtin_layout(name):
    ms = load_markerset(name)
    assert find_markerset([f"Subject:{label}" for label in ms.labels]).name == name


@pytest.mark.slow
def test_clean_keeps_the_markers_cut_with_a_head_reference_close_to_a_spline(realdata):
    """The AnimFace jaw take, three markers cut for 250 ms, one of them a head reference: the
    cleaned markers there stay within 2x a spline's error (3.5x before the pose was bridged)."""

    from capture import load_take

    take = load_take(realdata / "facial" / "animface" / "JawMoCap.csv", units="cm")
    ms = find_markerset(take.labels)
    refs = [take.index(ms.match(take.labels)[r]) for r in ms.head_reference]
    rng = np.random.default_rng(0)
    ours, spline = [], []
    for _ in range(12):
        n, start = 15, int(rng.integers(30, take.frames - 45))
        cut_markers = [*rng.choice([m for m in range(take.markers) if m not in refs], 2, replace=False),
                       int(rng.choice(refs))]
        cut = take.positions.copy()
        cut[start:start + n, cut_markers] = np.nan
        cleaned, _ = clean_take(Take(cut, take.labels, take.rate, take.times), CleanSettings(), ms)
        for m in cut_markers:
            truth = take.positions[start:start + n, m]
            seen = np.isfinite(cut[:, m, 0])
            guess = CubicSpline(take.times[seen], cut[seen, m], axis=0)(take.times[start:start + n])
            ours.append(np.linalg.norm(cleaned.positions[start:start + n, m] - truth, axis=1).mean())
            spline.append(np.linalg.norm(guess - truth, axis=1).mean())
    assert np.mean(ours) < 2.0 * np.mean(spline), (np.mean(ours), np.mean(spline))


def test_a_head_reference_spike_with_few_references_seen_does_not_turn_the_head():
    """Both temples lost for a second leave three references near the midline, which fix the
    head's yaw over a short lever; a 6 mm spike on the nose tip then turned the whole head by
    18 degrees (found on the second bench performer). The references'
    own spikes are found first, in the world, where the head's smooth motion bends no path; and
    three references on one line pin no yaw at all, so that second's pose is carried across from
    either side (mapping.stabilise.well_posed, mapping.lost_poses)."""
    syn = synthesize(rate=60.0, noise_mm=0.2, performance=default_performance(8, max_turn_deg=30), seed=4)
    pos = syn.take.positions.copy()
    for label in ("TEMPLE_R", "TEMPLE_L"):
        pos[240:300, syn.take.index(label)] = np.nan
    spiked = pos.copy()
    spiked[270, syn.take.index("NOSE_TIP")] += [6.0, 0.0, 0.0]
    markerset = load_markerset("toon32")
    yaw = [yaw_pitch_degrees(clean_stabilised(Take(p, syn.take.labels, 60.0), markerset)[0].rotation[260:281])[0]
           for p in (spiked, pos)]
    assert np.isfinite(yaw[0]).all()  # carried across, not left to gap filling
    assert np.nanmax(np.abs(yaw[0] - yaw[1])) < 1.0  # degrees; the spike turned it by 18


def test_the_midline_references_alone_pin_no_head_pose():
    """Forehead, nose bridge and nose tip lie on the face's midline: a fit on them alone turned
    the head by degrees with 0.3 mm of jitter, so it is no fit (as two references are none),
    while any three with a temple stand."""
    ms = load_markerset("toon32")
    shape = np.array([ms.neutral_of(r) for r in ms.head_reference])
    rng = np.random.default_rng(3)
    target = np.broadcast_to(shape, (200, len(shape), 3)) + rng.normal(0.0, 0.3, (200, len(shape), 3))
    midline = target.copy()
    midline[:, [1, 2, 5, 6]] = np.nan  # both temples and both inner eye corners lost
    one_temple = target.copy()
    one_temple[:, [2, 4]] = np.nan
    _, _, ok_mid = robust_rigid_fit(shape, midline)
    rot, _, ok_temple = robust_rigid_fit(shape, one_temple)
    raw_rot, _, raw_ok = rigid_fit(shape, midline)
    assert not ok_mid.any() and ok_temple.all() and raw_ok.all()
    yaw_spread = [float(np.std(yaw_pitch_degrees(r)[0])) for r in (raw_rot, rot)]
    assert yaw_spread[0] > 1.0 > 3 * yaw_spread[1], yaw_spread  # degrees: why the midline fit is refused


def test_a_lost_pose_is_carried_across_by_the_poses_that_are_pinned_best():
    """A fit on three references near a line, just before a lost stretch, is 4 mm and 3 degrees
    off; weighed by how well its references pin the head, it hardly bends the carried pose."""
    from scipy.spatial.transform import Rotation

    from mapping.lost_poses import bridge_lost_poses

    times = np.arange(120) / 60.0
    rotation, translation = np.tile(np.eye(3), (120, 1, 1)), np.zeros((120, 3))
    ok = np.ones(120, bool)
    ok[50:60] = False
    rotation[47:50] = Rotation.from_euler("y", 3.0, degrees=True).as_matrix()
    translation[47:50] = [4.0, 0.0, 0.0]
    trust = np.ones(120)
    trust[47:50] = 0.01  # three references on a line: a twentieth of all five's least moment, or less
    for weights, near in ((trust, True), (None, False)):
        _, carried, bridged = bridge_lost_poses(rotation, translation, ok, times, trust=weights)
        assert bridged[50:60].all() and not bridged[:50].any()
        assert (np.abs(carried[50:60, 0]).max() < 0.5) == near, (weights is None, carried[50:60, 0])


def test_a_nod_that_stops_while_the_temples_are_lost_follows_the_midline_references():
    """The head nods 20 degrees and stops inside half a second without either temple (found on
    the second bench performer): the pose carried across from either side cuts the corner by
    degrees, and every marker in the head frame moved by up to 14 mm. The forehead, nose bridge
    and nose tip still seen pin a nod well (not a turn about their line), so the carried pose
    follows them there, weighed as one fit on all five references (7.7 degrees off -> 4.7 at
    worst, the nod's own error mostly: the carried pose's doubt about the turn is kept); with
    no reference seen it stays as carried."""
    from scipy.spatial.transform import Rotation

    from mapping.lost_poses import bridge_lost_poses, refine_poses

    ms = load_markerset("toon32")
    shape = np.array([ms.neutral_of(r) for r in ms.head_reference])
    times = np.arange(120) / 60.0
    pitch = -20.0 * np.clip((times - 0.5) / 0.35, 0.0, 1.0)  # degrees: a nod from 0.5 s that stops at 0.85 s
    rotation = Rotation.from_euler("x", pitch[:, None], degrees=True).as_matrix()
    translation = np.tile([5.0, -3.0, 600.0], (120, 1))
    target = np.einsum("fij,kj->fki", rotation, shape) + translation[:, None, :]
    target += np.random.default_rng(5).normal(0.0, 0.3, target.shape)
    lost = np.zeros(120, bool)
    lost[36:63] = True  # 0.6-1.05 s: the nod's second half and its stop
    target[np.ix_(lost, [1, 2])] = np.nan
    carried_rot, carried_trans, bridged = bridge_lost_poses(rotation, translation, ~lost, times)
    assert (bridged == lost).all()
    refined_rot, _ = refine_poses(carried_rot, carried_trans, shape, target, bridged)

    def error(rot):  # degrees from the true pose, per lost frame
        rel = np.einsum("fji,fjk->fik", rotation[lost], rot[lost])
        return np.degrees(np.arccos(np.clip((np.trace(rel, axis1=1, axis2=2) - 1) / 2, -1.0, 1.0)))

    assert error(carried_rot).max() > 7.0 > 5.0 > error(refined_rot).max(), (error(carried_rot).max(),
                                                                             error(refined_rot).max())
    unseen = target.copy()
    unseen[lost] = np.nan
    kept_rot, kept_trans = refine_poses(carried_rot, carried_trans, shape, unseen, bridged)
    np.testing.assert_allclose(kept_rot, carried_rot, atol=1e-9)
    np.testing.assert_allclose(kept_trans, carried_trans, atol=1e-6)


def test_a_nod_seen_by_the_temples_alone_follows_the_faces_other_markers():
    """Two temples cannot pin a nod about the line through them: where only they are seen, the
    carried pose cut the corner of a nod that stops (second bench performer, draw 9: 6.6 degrees,
    3-5 mm on the pupils and mouth). The face's other markers, weighed by how little they move
    in the head, pin it; the mouth, which speaks through the whole take, hardly counts even
    where it opens inside the stretch."""
    from scipy.spatial.transform import Rotation

    from mapping.lost_poses import bridge_lost_poses, refine_poses, weak_references

    ms = load_markerset("toon32")
    shape = np.array([ms.neutral_of(r) for r in ms.head_reference])
    face_labels = [label for label in ms.labels if label not in ms.head_reference]
    face = np.array([ms.neutral_of(label) for label in face_labels])
    frames, rng = 120, np.random.default_rng(9)
    times = np.arange(frames) / 60.0
    local = np.repeat(face[None], frames, axis=0)
    speaking = face[:, 1] < -50  # the mouth and chin: open and shut all through, and wide open in the stretch
    opening = 4.0 + 4.0 * np.sin(2 * np.pi * 3 * times) + 6.0 * ((times > 0.6) & (times < 1.05))
    local[:, speaking, 1] -= opening[:, None]
    pitch = -20.0 * np.clip((times - 0.5) / 0.35, 0.0, 1.0)  # degrees: a nod from 0.5 s that stops at 0.85 s
    rotation = Rotation.from_euler("x", pitch[:, None], degrees=True).as_matrix()
    translation = np.tile([5.0, -3.0, 600.0], (frames, 1))
    target = np.einsum("fij,kj->fki", rotation, shape) + translation[:, None, :] \
        + rng.normal(0.0, 0.3, (frames, len(shape), 3))
    world = np.einsum("fij,fkj->fki", rotation, local) + translation[:, None, :] + rng.normal(0.0, 0.3, local.shape)
    lost = np.zeros(frames, bool)
    lost[36:63] = True  # 0.6-1.05 s: only the temples seen
    target[np.ix_(lost, [0, 3, 4, 5, 6])] = np.nan
    carried_rot, carried_trans, bridged = bridge_lost_poses(rotation, translation, ~lost, times)
    seen_local = np.einsum("fji,fkj->fki", rotation, world - translation[:, None, :])  # in the fitted frames' heads
    seen_local[lost] = np.nan
    weak = weak_references(seen_local, world, ~lost, bridged, times, noise=0.3)
    plain_rot, _ = refine_poses(carried_rot, carried_trans, shape, target, bridged)
    weak_rot, _ = refine_poses(carried_rot, carried_trans, shape, target, bridged, weak=weak)

    def error(rot):  # degrees from the true pose, worst lost frame
        rel = np.einsum("fji,fjk->fik", rotation[lost], rot[lost])
        return np.degrees(np.arccos(np.clip((np.trace(rel, axis1=1, axis2=2) - 1) / 2, -1.0, 1.0))).max()

    assert error(carried_rot) > 7.0 and error(plain_rot) > 7.0  # the temples alone leave the nod as carried
    assert error(weak_rot) < 4.5, error(weak_rot)  # 7.3 -> 4.1 at worst: the carried pose keeps its own weight
    assert weak.weight[lost][:, speaking].max() < 0.05 < 0.4 < weak.weight[lost][:, ~speaking].min()
    assert (weak.weight[~lost] == 0).all()


def test_a_performer_whose_head_references_sit_apart_from_the_sets_keeps_the_head_still_when_one_drops():
    """The references' own shape is measured in a head fitted with the marker set's, and then
    again in the head fitted with that, until it settles. Measured once, on this draw of the
    third performer (temples 7-8 mm wider than toon32's, the forehead 4.5 mm lower) it kept
    the temples 1.8 mm too narrow: every fit without one reference turned the head by 2-7
    degrees, and the whole face by as much, for as long as it was lost."""
    from bench.third_performer import YAW_DEGREES, perform

    third = perform(seconds=20.0, seed=19)
    take, markerset = third.take, load_markerset("toon32")
    rows = [take.labels.index(label) for label in markerset.head_reference]
    neutral = np.array([markerset.neutral_of(label) for label in markerset.head_reference])
    stable = stabilise(take.positions, rows, neutral)
    fitted_yaw, _ = yaw_pitch_degrees(stable.rotation)
    missed = fitted_yaw - 2 * YAW_DEGREES * (third.motors[:, MOTOR_CODES.index("HH")] - 0.5)
    missed = np.abs(missed - np.nanmedian(missed))  # the head frame's own zero is the rest's business
    lost = np.isnan(take.positions[:, rows, 0]).any(axis=1)
    assert lost.mean() > 0.2 and np.nanpercentile(missed[lost], 95) < 1.0 and np.nanmean(missed[lost]) < 0.3, \
        (np.nanpercentile(missed[lost], [50, 95, 99]), np.nanmean(missed[lost]))


@pytest.mark.parametrize("stretch", [(1.13, 1.0, 1.0), (0.88, 1.0, 1.0), (1.1, 0.9, 1.12)])
def test_a_correctly_labelled_face_of_other_proportions_raises_no_label_warning(stretch):
    """Issue 66: a toon32 performer 10-15 % wider or narrower heard "the head references lie 7-11
    mm from the marker set's shape: are the labels in the right order?" on every take."""
    from mapping import choose_mapping, prepare
    from mapping.take_notes import stabilisation_notes

    syn = synthesize(seconds=3.0, noise_mm=0.0, performance=default_performance(3.0, max_turn_deg=0))
    take = syn.take
    centre = np.nanmean(take.positions[0], axis=0)
    wide = Take((take.positions - centre) * np.array(stretch) + centre, take.labels, take.rate, times=take.times)
    prepared = prepare(wide, choose_mapping(wide)[1])
    expected = np.array([prepared.markerset.neutral_of(r) for r in prepared.markerset.head_reference])
    raw = np.sqrt(np.mean(np.sum((prepared.stable.reference - expected)[:5] ** 2, axis=1)))
    assert raw > 5.0  # in raw millimetres the old check warned (on the five at the face's edges)
    assert not [n for n in stabilisation_notes(prepared) if "head references" in n]
    swapped = list(wide.labels)
    a, b = swapped.index("TEMPLE_R"), swapped.index("TEMPLE_L")
    swapped[a], swapped[b] = swapped[b], swapped[a]  # a real mistake is still said
    mistaken = Take(wide.positions, tuple(swapped), wide.rate, times=wide.times)
    prepared = prepare(mistaken, choose_mapping(mistaken)[1])
    assert [n for n in stabilisation_notes(prepared) if "head references" in n]
