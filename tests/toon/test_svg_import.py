"""An SVG drawing as a face's components: shapes in document order with their transforms, fills,
strokes and widths, fitted into the face's viewbox with y turned up; curves as a few points,
straight edges as their corners; bad drawings refused in a line. And attached to a feature, a
component moves with the face's control points."""

import numpy as np
import pytest

from common import InputError
from toon import FaceRig, load_face, motor_index
from toon.face import face_from_dict
from toon.svg_import import svg_components
from toonface.studio import component_edits as parts

DRAWING = """<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 200">
  <g transform="translate(20, 0) scale(0.5)"><rect id="patch" x="0" y="0" width="40" height="20" fill="#336699"/></g>
  <path id="mouth" d="M60 140 Q100 170 140 140 Q100 155 60 140 Z" fill="#b0303a" stroke="#000" stroke-width="2"/>
  <polyline id="lash" points="10,10 20,5 30,10" fill="none" stroke="rgba(0,0,0,0.5)" stroke-width="4"/>
  <circle cx="100" cy="100" r="3" fill="none" stroke="none"/>
  <circle id="blush" cx="50" cy="100" r="10" fill="#ff0000" opacity="0.5"/>
</svg>"""


def test_shapes_become_components_in_order_fitted_into_the_face_with_y_up():
    made = svg_components(DRAWING, (-256.0, -256.0, 256.0, 256.0))
    assert [c["name"] for c in made] == ["patch", "mouth", "lash", "blush"]  # the invisible circle left out
    patch, mouth, lash, blush = made
    assert blush["fill"] == "#ff000080"  # its own opacity
    scale = 512 / 200  # the 200-unit drawing fills the 512-unit face
    # the rect, translated then scaled by its group: (20, 0)..(40, 10) in the drawing, four corners
    expected = [((x - 100) * scale, -(y - 100) * scale) for x, y in ((20, 0), (40, 0), (40, 10), (20, 10))]
    assert patch["kind"] == "polygon" and np.allclose(patch["points"], expected, atol=1e-3)
    assert patch["fill"] == "#336699" and "stroke" not in patch
    assert mouth["kind"] == "polygon" and mouth["fill"] == "#b0303a" and mouth["stroke"] == "#000000"
    assert mouth["width"] == pytest.approx(2 * scale)
    assert 4 <= len(mouth["points"]) <= 64
    ys = np.array(mouth["points"])[:, 1]
    assert ys.max() == pytest.approx(-(140 - 100) * scale, abs=1e-3)  # its top, the corners, below the centre
    assert lash["kind"] == "polyline" and lash["stroke"] == "#00000080" and len(lash["points"]) == 3


@pytest.mark.parametrize("text, says", [("<svg", "not an SVG drawing"), ("<html/>", "not an SVG drawing"),
                                        ('<svg xmlns="http://www.w3.org/2000/svg"/>', "no shape"),
                                        ('<svg xmlns="http://www.w3.org/2000/svg"><rect width="9" height="9" '
                                         'fill="none"/></svg>', "empty, invisible or specks")])
def test_a_drawing_that_draws_nothing_is_refused_in_a_line(text, says):
    with pytest.raises(ValueError, match=says):
        svg_components(text, (-256.0, -256.0, 256.0, 256.0))


def test_a_component_attached_to_the_mouth_moves_with_it():
    doc = load_face("classic").to_dict()
    [_, mouth, *_] = parts.import_svg(doc, DRAWING)
    parts.attach(doc, mouth, "mouth")
    spec = doc["components"][mouth]
    follows = [ref["slave"] if isinstance(ref["slave"], dict) else {ref["slave"]: 1.0} for ref in spec["points"]]
    assert set().union(*follows) <= {"ML", "MT", "MR", "MB"}
    assert all(len(f) <= 2 and abs(sum(f.values()) - 1) < 1e-9 for f in follows)
    assert any(len(f) == 2 for f in follows)  # points between two control points follow both
    face = face_from_dict(doc)
    rig = FaceRig(face)
    shut, open_ = face.neutral(), face.neutral()
    open_[motor_index("MB")] = 1.0
    name = spec["name"]
    shapes = [next(i.vertices for i in rig.geometry(v).items if i.name == name) for v in (shut, open_)]
    assert not np.allclose(shapes[0], shapes[1])  # it moved as the mouth opened
    with pytest.raises(ValueError, match="attach to one of mouth"):
        parts.attach(doc, mouth, "nose")


def test_a_slave_of_two_masters_moves_by_its_share_of_each_and_reads_back():
    """A point halfway between a mouth corner and the mouth's bottom, a slave of both at 0.5:
    when the jaw drops it drops half as far (by hand), where a slave of the bottom alone drops as
    far as the bottom does; the face file keeps the weights."""
    face = load_face("classic")
    doc = face.to_dict()
    ml, mb = np.array(face.points["ML"]), np.array(face.points["MB"])
    mid = (0.5 * ml + 0.5 * mb).tolist()
    doc["components"] = [*doc.get("components", []),
                         {"kind": "polyline", "name": "both", "stroke": "#000000", "width": 2,
                          "points": ["ML", {"slave": {"ML": 0.5, "MB": 0.5}, "at": mid}, "MB"]},
                         {"kind": "polyline", "name": "one", "stroke": "#000000", "width": 2,
                          "points": ["ML", {"slave": "MB", "at": mid}, "MB"]}]
    blended = face_from_dict(doc)
    rig = FaceRig(blended)
    shut, open_ = blended.neutral(), blended.neutral()
    open_[motor_index("MB")] = 1.0
    drop = rig.control_points(open_) - rig.control_points(shut)
    names = list(blended.points)
    for item, share in (("both", 0.5), ("one", 1.0)):
        before, after = (next(i.vertices for i in rig.geometry(v).items if i.name == item) for v in (shut, open_))
        expected = share * drop[names.index("MB")] + (0.5 if item == "both" else 0.0) * drop[names.index("ML")]
        np.testing.assert_allclose(after[1] - before[1], expected, atol=1e-9)
    assert blended.to_dict()["components"][-2]["points"][1] == {"slave": {"ML": 0.5, "MB": 0.5}, "at": mid}
    doc["components"][-2]["points"][1]["slave"] = {"ML": 0.5, "MB": 0.4}
    with pytest.raises(InputError, match="weights must sum to 1"):
        face_from_dict(doc)


def test_a_gradient_becomes_its_mean_colour_said_aloud_and_groups_fade_their_shapes():
    """A gradient fill came in black and nothing said so; a group's opacity was lost on a shape
    with its own. Red to half-clear blue (Inkscape's way: the stops in another gradient it
    points to), in a group at half opacity: by hand, the mean (0.5, 0, 0.5) at 0.75 alpha, faded
    by the group's half; the circle's own half times the group's."""
    drawing = """<svg xmlns="http://www.w3.org/2000/svg" xmlns:xlink="http://www.w3.org/1999/xlink"
      viewBox="0 0 100 100"><defs>
      <linearGradient id="stops"><stop offset="0" stop-color="#ff0000"/>
        <stop offset="1" style="stop-color:#0000ff;stop-opacity:0.5"/></linearGradient>
      <linearGradient id="g" xlink:href="#stops" x1="0" x2="1"/></defs>
      <g opacity="0.5"><rect id="r" x="10" y="10" width="50" height="50" fill="url(#g)"/>
        <circle id="c" cx="70" cy="70" r="10" fill="#00ff00" style="opacity:0.5"/>
        <rect id="lost" x="0" y="0" width="9" height="9" fill="url(#nowhere)" stroke="#000000"/></g></svg>"""
    notes: list[str] = []
    made = {spec["name"]: spec for spec in svg_components(drawing, (-256.0, -256.0, 256.0, 256.0), notes)}
    assert made["r"]["fill"] == f"#800080{round(255 * 0.75 * 0.5):02x}"
    assert made["c"]["fill"] == f"#00ff00{round(255 * 0.25):02x}"
    assert "fill" not in made["lost"] and made["lost"]["stroke"] == "#00000080"
    assert notes == ["r: its gradient fill became its mean colour #800080",
                     "lost: its fill (url(#nowhere)) names no gradient with stops: left out"]
