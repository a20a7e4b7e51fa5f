"""The GL renderer against the CPU rasteriser, on exact small readbacks."""

import numpy as np
import pytest

from player import Renderer
from player.renderer import triangulate
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


def test_a_kept_triangulation_is_reused_only_while_it_still_tiles_the_outline():
    from player.renderer import Triangulator, triangles_of

    def area(geom, tri):
        data, _ = triangles_of(geom, tri)
        t = data[:, :2].astype(float).reshape(-1, 3, 2)
        u, v = t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]
        return np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]).sum() / 2

    tri = Triangulator()
    square = _poly([[0, 0], [4, 0], [4, 4], [0, 4]], WHITE)
    assert area(Geometry((square,), VIEW, WHITE), tri) == pytest.approx(16)
    moved = _poly([[0, 0], [6, 0], [6, 5], [0, 4]], WHITE)  # same topology: re-used
    assert area(Geometry((moved,), VIEW, WHITE), tri) == pytest.approx(27) and tri.reused == 1
    # A dart whose reflex vertex puts the kept diagonal outside it: re-using that triangulation
    # would leave a flipped triangle (covered area 10, not 6).
    kept = tri.kept(moved).reshape(-1, 3)
    shared = sorted(set(kept[0]) & set(kept[1]))
    dart = [[0, 0], [4, 2], [0, 4], [1, 2]]  # reflex at 3: diagonal 0-2 lies outside
    if shared == [1, 3]:
        dart = dart[-1:] + dart[:-1]  # reflex at 0: diagonal 1-3 lies outside
    dart = _poly(dart, WHITE)
    assert area(Geometry((dart,), VIEW, WHITE), tri) == pytest.approx(6)
    computed = tri.computed
    notch = _poly([[0, 0], [4, 0], [4, 4], [2, 1], [0, 4]], WHITE)  # more vertices: triangulated afresh
    assert area(Geometry((notch,), VIEW, WHITE), tri) == pytest.approx(10) and tri.computed == computed + 1


def test_a_clockwise_outline_keeps_its_triangulation_too():
    # earcut emits a clockwise outline's triangles counter-clockwise; the re-use check compares
    # against the winding they had when made, so a clockwise fill is not triangulated every frame.
    from player.renderer import Triangulator, triangles_of

    tri = Triangulator()
    for shift in (0.0, 0.5, 1.0):
        clockwise = _poly([[0, 0], [0, 4], [4 + shift, 4], [4, 0]], WHITE)
        triangles_of(Geometry((clockwise,), VIEW, WHITE), tri)
    assert (tri.computed, tri.reused) == (1, 2)
    folded = _poly([[0, 0], [0, 4], [-4, 4], [4, 0]], WHITE)  # a vertex swung across: not re-used
    triangles_of(Geometry((folded,), VIEW, WHITE), tri)
    assert tri.computed == 2
