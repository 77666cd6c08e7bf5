"""model/scene/rim.py: the texture interior, the textured pixels less a one-pixel rim at every silhouette."""
import numpy as np

from model.scene.rim import silhouette_rim, texture_interior


def _rect(H, W, y0, y1, x0, x1):
    m = np.zeros((H, W), bool)
    m[y0:y1, x0:x1] = True
    return m


def test_rim_is_one_pixel_on_both_sides_of_an_edge():
    m = _rect(10, 10, 3, 7, 2, 8)  # rows 3..6, columns 2..7
    rim = silhouette_rim([m])
    # inside: rows 4..5, columns 3..6 have a 3x3 neighbourhood inside the rectangle
    inside = _rect(10, 10, 4, 6, 3, 7)
    # outside: more than one pixel from the rectangle
    grown = _rect(10, 10, 2, 8, 1, 9)
    assert (rim == (grown & ~inside)).all()
    assert (texture_interior([m]) == inside).all()


def test_frame_border_is_not_an_edge():
    full = np.ones((6, 6), bool)
    assert not silhouette_rim([full]).any()
    assert texture_interior([full]).all()
    left = _rect(6, 6, 0, 6, 0, 3)  # the left half, touching three borders
    rim = silhouette_rim([left])
    assert (rim == _rect(6, 6, 0, 6, 2, 4)).all()


def test_an_edge_between_two_passes_is_a_rim():
    # a moon in front of a planet: both cover the pixels beside the moon's edge, whose truth mixes the two
    planet = np.ones((12, 12), bool)
    moon = _rect(12, 12, 4, 8, 4, 8)
    inner = texture_interior([moon, planet])
    assert not inner[3:9, 3:9][[0, -1], :].any() and not inner[3:9, 3:9][:, [0, -1]].any()
    assert inner[5:7, 5:7].all() and inner[0:2, :].all()
    assert inner.sum() == 144 - (6 * 6 - 2 * 2)


def test_empty_and_shapes():
    assert silhouette_rim([]).shape == (0, 0)
    m = np.zeros((3, 5), bool)
    assert texture_interior([m]).shape == (3, 5) and not texture_interior([m]).any()
