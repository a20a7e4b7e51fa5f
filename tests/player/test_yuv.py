"""RGB to yuv420p for the H.264 encoder: Rec. 601 limited range, chroma at H.264's default place."""

import numpy as np
import pytest

from player.yuv import rgb_to_i420

#: Rec. 601 (ITU-R BT.601-7) in limited range, 8 bits: Y, Cb, Cr from R, G, B in 0-255
RGB_TO_YCC = np.array([[65.481, 128.553, 24.966], [-37.797, -74.203, 112.0], [112.0, -93.786, -18.214]]) / 255
OFFSET = np.array([16.0, 128.0, 128.0])


def _by_hand(rgb):
    """The same conversion in floats, rounded once: chroma from each pair of rows' mean, weighed
    1/4, 1/2, 1/4 over the columns left of, at and right of each even column."""
    ycc = rgb.astype(float) @ RGB_TO_YCC.T + OFFSET
    rows = (ycc[0::2] + ycc[1::2]) / 2
    left = np.concatenate([rows[:, :1], rows[:, 1:-1:2]], axis=1)  # column 2j - 1 (the first column at j = 0)
    chroma = rows[:, 0::2] / 2 + (left + rows[:, 1::2]) / 4
    planes = [ycc[..., 0], chroma[..., 1], chroma[..., 2]]
    return np.concatenate([np.rint(p).reshape(-1) for p in planes])


@pytest.mark.parametrize("shape", [(64, 48), (6, 10), (2, 2)])
def test_every_sample_is_within_one_of_the_conversion_worked_in_floats(shape):
    rng = np.random.default_rng(3)
    noise = rng.integers(0, 256, (*shape, 3), dtype=np.uint8)
    blocks = np.kron(rng.integers(0, 256, (shape[0], shape[1], 3)), np.ones((3, 5, 1))).astype(np.uint8)
    for image in (noise, np.ascontiguousarray(blocks[:shape[0], :shape[1]])):
        out = rgb_to_i420(image)
        assert out.shape == (shape[0] * 3 // 2, shape[1]) and out.dtype == np.uint8
        assert np.abs(out.reshape(-1).astype(int) - _by_hand(image)).max() <= 1


def test_chroma_sits_on_the_left_column_of_each_pair():
    # a white line on grey: on an even column 2j only chroma sample j sees it (weight 1/2); on an
    # odd column 2j + 1 samples j and j + 1 share it (1/4 each); a box over each pair of columns
    # would give sample j all of both
    for column, weights in ((6, {3: 0.5}), (7, {3: 0.25, 4: 0.25})):
        image = np.full((4, 16, 3), 128, np.uint8)
        image[:, column] = (255, 0, 0)
        cr = rgb_to_i420(image)[4 + 1:].reshape(2, 8)[0].astype(float)  # after 4 luma rows and Cb's 1
        grey = 128.0  # Cr of any grey
        step = RGB_TO_YCC[2] @ (np.array([255.0, 0.0, 0.0]) - 128.0)  # Cr of red less Cr of grey
        rise = {j: step * w for j, w in weights.items()}
        for j in range(8):
            assert abs(cr[j] - (grey + rise.get(j, 0.0))) <= 1, (column, j, cr.tolist())


def test_odd_sides_are_refused():
    with pytest.raises(ValueError, match="even sides"):
        rgb_to_i420(np.zeros((3, 4, 3), np.uint8))
