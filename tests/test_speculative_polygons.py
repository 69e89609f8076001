"""The engine's speculative polygon manifolds (narrowphase/manifold.py, polygons.py:
speculative_polygons) against shapely: every pair closer than the margin gets its manifold, with
the true gap, and none farther does."""
import numpy as np
import pytest
from shapely.geometry import Polygon
from test_polygon_narrowphase import ellipse_polygons

from collisim.narrowphase.manifold import _polygons
from collisim.narrowphase.polygons import speculative_polygons

MARGIN = 0.3


@pytest.fixture(scope="module")
def near_pairs():
    """(a, b, distance) of 3000 seeded pairs apart by less than twice the margin."""
    rng = np.random.default_rng(7)
    found = []
    while len(found) < 3000:
        a, b = ellipse_polygons(rng, 1), ellipse_polygons(rng, 1, spread=2.5)
        a, b = np.ascontiguousarray(a[0]), np.ascontiguousarray(b[0])
        distance = Polygon(a).distance(Polygon(b))
        if 0.0 < distance < 2 * MARGIN:
            found.append((a, b, distance))
    return found


def test_every_pair_within_the_margin_gets_its_manifold_with_the_true_gap(near_pairs):
    within = 0
    for a, b, distance in near_pairs:
        m = _polygons(a, b, MARGIN)
        if distance < MARGIN * (1 - 1e-9):
            within += 1
            assert m[2] > 0, (a.tolist(), b.tolist(), distance)
            assert -m[3] == pytest.approx(distance, rel=1e-9, abs=1e-12)
            assert np.hypot(m[0], m[1]) == pytest.approx(1.0, abs=1e-12)
        elif distance > MARGIN * (1 + 1e-9):
            assert m[2] == 0
    assert within > 1000


def test_a_vertex_over_a_face_needs_no_closest_points(near_pairs):
    """speculative_polygons alone finds most near pairs (vertex over face), with the true gap;
    the rest are corner against corner, left to the closest points."""
    found = 0
    for a, b, distance in near_pairs:
        m = speculative_polygons(a, b, MARGIN)
        if m[2] > 0:
            found += 1
            assert -m[3] == pytest.approx(distance, rel=1e-9, abs=1e-12)
    assert found > 0.5 * sum(d < MARGIN for _, _, d in near_pairs)


@pytest.mark.parametrize("angle", [0.002, -0.02])
def test_a_tilted_box_touching_another_keeps_its_raised_corner_within_the_margin(angle):
    """One corner a hair into the box below, the other raised by less than the margin: two
    points, the second as far apart as the raised corner is (Box2D keeps clipped points up to
    its speculative distance, touching or not)."""
    from collisim.shapes import box
    c, s = np.cos(angle), np.sin(angle)
    top = np.asarray(box(1.0, 0.5)) @ np.array([[c, s], [-s, c]])
    top = np.ascontiguousarray(top + (0.0, 0.25 - top[:, 1].min() - 0.001))
    below = np.ascontiguousarray(np.asarray(box(2.0, 0.5), float))
    raised = sorted(top[:, 1] - 0.25)[1]
    assert 0.0 < raised < MARGIN
    m = _polygons(top, below, MARGIN)
    assert m[2] == 2
    np.testing.assert_allclose(sorted([m[3], m[6]]), sorted([0.001, -raised]), atol=1e-9)
