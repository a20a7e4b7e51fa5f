"""The GL renderer against the CPU rasteriser, on exact small readbacks."""

import numpy as np
import pytest

from player import Renderer
from player.layout import FramePlanner, triangulate
from toon import DrawItem, FaceRig, Geometry, load_face, motor_index, render_cpu, standard_neutral

VIEW = (0.0, 0.0, 16.0, 16.0)
WHITE = (1.0, 1.0, 1.0, 1.0)


def _poly(vertices, color, kind="free", mask=0):
    write = mask if kind == "hole" else 0
    test = mask if kind == "pupil" else (0 if kind == "face" else None)
    return DrawItem(np.asarray(vertices, dtype=float), color, kind=kind, mask_write=write, mask_test=test)


def test_a_concave_polygon_fills_exactly_like_the_cpu(ctx):
    # An L-shape in a 16x16 face-unit view; 1 unit = 1 pixel, y up.
    ell = _poly([[2, 2], [14, 2], [14, 6], [6, 6], [6, 14], [2, 14]], (1.0, 0.0, 0.0, 1.0))
    geom = Geometry((ell,), VIEW, (0.0, 0.0, 0.0, 1.0))
    with Renderer(ctx, (16, 16), samples=0) as r:
        gpu = r.render(geom)
    cpu = render_cpu(geom, (16, 16))
    np.testing.assert_array_equal(gpu, cpu)
    assert gpu[:, :, 0].sum() // 255 == 12 * 4 + 4 * 8  # the L's area in pixels
    # Row 0 is the top (y = 16): the foot of the L is at the bottom, its notch at the top right.
    assert gpu[13, 12, 0] == 255 and gpu[4, 3, 0] == 255 and gpu[4, 12, 0] == 0


def test_holes_mask_pupils_and_face(ctx):
    hole = _poly([[2, 2], [8, 2], [8, 8], [2, 8]], (0.0, 0.0, 1.0, 1.0), "hole", 1)
    pupil = _poly([[5, 5], [12, 5], [12, 12], [5, 12]], (0.0, 1.0, 0.0, 1.0), "pupil", 1)
    face = _poly([[0, 0], [16, 0], [16, 16], [0, 16]], (1.0, 0.0, 0.0, 1.0), "face")
    geom = Geometry((hole, pupil, face), VIEW, (0.0, 0.0, 0.0, 1.0))
    with Renderer(ctx, (16, 16), samples=0) as r:
        gpu = r.render(geom)
    np.testing.assert_array_equal(gpu, render_cpu(geom, (16, 16)))
    assert tuple(gpu[16 - 6, 6]) == (0, 255, 0)  # pupil inside the hole
    assert tuple(gpu[16 - 10, 10]) == (255, 0, 0)  # pupil outside the hole: covered by the face
    assert tuple(gpu[16 - 3, 3]) == (0, 0, 255)  # hole not covered by the face


@pytest.mark.parametrize("pose", ["neutral", "smile_turn", "lids_down_open_mouth"])
def test_default_face_64px_matches_the_cpu_oracle(ctx, pose):
    values = standard_neutral()
    if pose == "smile_turn":
        for code, v in (("MLV", 0.9), ("MRV", 0.9), ("MLH", 0.8), ("MRH", 0.8), ("HH", 0.85), ("HV", 0.6)):
            values[motor_index(code)] = v
    elif pose == "lids_down_open_mouth":
        # Half-closed lids: fully closed ones touch the lower lid, and earcut and the even-odd
        # rule legitimately disagree on such degenerate polygons.
        for code, v in (("ERU", 0.3), ("ELU", 0.3), ("MB", 0.9), ("PRH", 1.0), ("PLH", 1.0)):
            values[motor_index(code)] = v
    geom = FaceRig(load_face("classic")).geometry(values)
    with Renderer(ctx, (64, 64), samples=0) as r:
        gpu = r.render(geom)
    cpu = render_cpu(geom, (64, 64))
    differ = np.any(np.abs(gpu.astype(int) - cpu.astype(int)) > 1, axis=2)
    # Only pixels whose centre lies on an edge may differ (GL's tie rule vs. the oracle's).
    assert differ.mean() < 0.005, f"{differ.sum()} of 4096 pixels differ"
    assert len(np.unique(cpu.reshape(-1, 3), axis=0)) >= 8  # a real picture, not a blank


def test_antialiased_frame_stays_close_to_the_oracle(ctx):
    geom = FaceRig(load_face("classic")).geometry(standard_neutral())
    with Renderer(ctx, (128, 128), samples=4) as r:
        smooth = r.render(geom)
    cpu = render_cpu(geom, (128, 128))
    diff = np.abs(smooth.astype(int) - cpu.astype(int)).max(axis=2)
    assert np.median(diff) == 0 and (diff > 8).mean() < 0.08
    edges = (diff > 0) & (diff < 200)
    assert edges.sum() > 100  # multisampling produced intermediate edge colours


def test_renderer_close_is_idempotent_and_blocks_use(ctx):
    r = Renderer(ctx, (8, 8))
    r.close()
    r.close()
    with pytest.raises(RuntimeError, match="closed"):
        r.render(Geometry((), VIEW, WHITE))


def test_empty_geometry_is_the_background(ctx):
    with Renderer(ctx, (8, 6), samples=4) as r:
        frame = r.render(Geometry((), VIEW, (0.2, 0.4, 0.6, 1.0)))
    assert frame.shape == (6, 8, 3)
    assert (frame == [51, 102, 153]).all()


def test_triangulation_covers_the_polygon_area():
    square_with_notch = np.array([[0, 0], [4, 0], [4, 4], [2, 1], [0, 4]], dtype=float)
    tris = square_with_notch[triangulate(square_with_notch)].reshape(-1, 3, 2)
    u, v = tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0]
    area = np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]).sum() / 2
    assert area == pytest.approx(16 - 4 * 3 / 2)


def _covered_area(planner, *items):
    layout, points = planner.plan(Geometry(tuple(items), VIEW, WHITE))
    t = layout.fill_corners(points).reshape(-1, 3, 2)
    u, v = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
    return np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]).sum() / 2


def test_a_kept_triangulation_is_reused_only_while_it_still_tiles_the_outline():
    planner = FramePlanner()
    tri = planner.triangulator
    square = _poly([[0, 0], [4, 0], [4, 4], [0, 4]], WHITE)
    assert _covered_area(planner, square) == pytest.approx(16)
    moved = _poly([[0, 0], [6, 0], [6, 5], [0, 4]], WHITE)  # same topology: re-used
    assert _covered_area(planner, moved) == pytest.approx(27) and (tri.computed, tri.reused) == (1, 1)
    # A dart whose reflex vertex puts the kept diagonal outside it: re-using that triangulation
    # would leave a flipped triangle (covered area 10, not 6).
    kept = tri.get(moved)[0].reshape(-1, 3)
    shared = sorted(set(kept[0]) & set(kept[1]))
    dart = [[0, 0], [4, 2], [0, 4], [1, 2]]  # reflex at 3: diagonal 0-2 lies outside
    if shared == [1, 3]:
        dart = dart[-1:] + dart[:-1]  # reflex at 0: diagonal 1-3 lies outside
    assert _covered_area(planner, _poly(dart, WHITE)) == pytest.approx(6) and tri.computed == 2
    notch = _poly([[0, 0], [4, 0], [4, 4], [2, 1], [0, 4]], WHITE)  # more vertices: triangulated afresh
    assert _covered_area(planner, notch) == pytest.approx(10) and tri.computed == 3


def test_a_clockwise_outline_keeps_its_triangulation_too():
    # earcut emits a clockwise outline's triangles counter-clockwise; the re-use check compares
    # against the winding they had when made, so a clockwise fill is not triangulated every frame.
    planner = FramePlanner()
    tri = planner.triangulator
    for shift in (0.0, 0.5, 1.0):
        _covered_area(planner, _poly([[0, 0], [0, 4], [4 + shift, 4], [4, 0]], WHITE))
    assert (tri.computed, tri.reused) == (1, 2)
    folded = _poly([[0, 0], [0, 4], [-4, 4], [4, 0]], WHITE)  # a vertex swung across: not re-used
    _covered_area(planner, folded)
    assert tri.computed == 2


def test_strokes_built_on_the_gpu_match_the_cpu_triangles(ctx):
    # Joins of every kind: a gentle turn (miter), a hairpin beyond the miter limit (bevel), a
    # zero-length segment, a hidden edge (no quad, no join into it), and a closed outline.
    zigzag = DrawItem(np.array([[3.3, 4.1], [20.2, 6.3], [36.7, 4.4], [22.1, 9.2], [22.1, 9.2], [40.6, 20.3],
                                [44.2, 40.1]]), None, (0.9, 0.1, 0.1, 1.0), 2.6, closed=False,
                      edge_visible=np.array([True, True, True, True, True, False]))
    box = DrawItem(np.array([[8.2, 24.3], [30.1, 26.2], [26.4, 44.7], [10.3, 40.2]]), (0.2, 0.6, 0.2, 1.0),
                   (0.1, 0.1, 0.8, 1.0), 3.4, closed=True, key=1)
    geom = Geometry((zigzag, box), (0.0, 0.0, 48.0, 48.0), WHITE)
    with Renderer(ctx, (96, 96), samples=0) as r:
        gpu = r.render(geom)
    cpu = render_cpu(geom, (96, 96))
    differ = np.any(gpu != cpu, axis=2)
    assert differ.sum() <= 3, f"{differ.sum()} pixels differ"
    red = np.all(gpu == [230, 26, 26], axis=2)
    assert red.sum() > 400  # the zigzag is there, hairpin and all
    shown = Geometry((zigzag.with_vertices(zigzag.vertices[:6]), box), geom.viewbox, WHITE)
    assert (np.all(render_cpu(shown, (96, 96)) == [230, 26, 26], axis=2) == red).all()  # hidden: not drawn


def test_one_renderer_switching_faces_and_visibility_matches_fresh_renderers(ctx):
    # Layouts are kept per structure: another face, or a component switched off by its motor
    # (the line face's open-mouth lines follow MB), must each get their own.
    def pose(face, mb):
        values = standard_neutral()
        values[motor_index("MB")] = mb
        return FaceRig(load_face(face)).geometry(values)

    frames = [pose("lines", 0.0), pose("lines", 1.0), pose("classic", 0.5), pose("lines", 0.0), pose("lines", 1.0)]
    assert len(frames[0].items) != len(frames[1].items)  # the switch really changes the structure
    with Renderer(ctx, (48, 48), samples=4) as shared:
        drawn = [shared.render(g) for g in frames]
    for geom, frame in zip(frames, drawn, strict=True):
        with Renderer(ctx, (48, 48), samples=4) as fresh:
            np.testing.assert_array_equal(frame, fresh.render(geom))
    assert not np.array_equal(drawn[0], drawn[1]) and np.array_equal(drawn[0], drawn[3])


def test_a_new_layout_checks_the_triangulations_it_takes_from_another():
    # The square's triangulation is kept by item key; a frame with another structure (a second
    # item shown) builds a new layout that takes it, and must still check it against the dart.
    planner = FramePlanner()
    square = _poly([[0, 0], [4, 0], [4, 4], [0, 4]], WHITE)
    assert _covered_area(planner, square) == pytest.approx(16)
    kept = planner.triangulator.get(square)[0].reshape(-1, 3)
    dart = [[0, 0], [4, 2], [0, 4], [1, 2]]  # reflex at 3: a diagonal 0-2 lies outside
    if sorted(set(kept[0]) & set(kept[1])) == [1, 3]:
        dart = dart[-1:] + dart[:-1]  # reflex at 0: diagonal 1-3 lies outside
    other = DrawItem(np.array([[10.0, 10.0], [12.0, 10.0], [12.0, 12.0]]), WHITE, key=1)
    assert _covered_area(planner, _poly(dart, WHITE), other) == pytest.approx(6 + 2)
    assert planner.triangulator.computed == 3  # square, the other triangle, the dart again
