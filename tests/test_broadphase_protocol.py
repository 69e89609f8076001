"""Box queries and ray casts: every broad phase against plain numpy references.

Like scipy's test_kdtree: one fixture runs each test on every method. Unlike
``pairs`` (which may report extra candidates), ``query`` and ``raycast`` are
exact: each method must return precisely the reference's boxes, and the same
entry distances to 1e-12 relative.
"""

import math

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from strategies import OPTIONS, box_arrays, coordinate, extent

from collisim.broadphase import PROTOCOL, make, query, raycast


@pytest.fixture(scope="module", params=PROTOCOL)
def method(request):
    return request.param


# ----------------------------------------------------- numpy references

def reference_query(lo, hi, box_lo, box_hi):
    """Indices of the boxes overlapping [box_lo, box_hi], touching included."""
    lo, hi = np.asarray(lo, float).reshape(-1, 2), np.asarray(hi, float).reshape(-1, 2)
    return np.flatnonzero(np.all((lo <= np.asarray(box_hi, float))
                                 & (np.asarray(box_lo, float) <= hi), axis=1))


def reference_raycast(lo, hi, origin, direction, max_distance):
    """Slab test on every box at once: (indices, t_enter) sorted by (t_enter, index)."""
    lo, hi = np.asarray(lo, float).reshape(-1, 2), np.asarray(hi, float).reshape(-1, 2)
    origin, direction = np.asarray(origin, float), np.asarray(direction, float)
    u = direction / math.hypot(*direction)
    with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
        t_a, t_b = (lo - origin) / u, (hi - origin) / u
    near, far = np.minimum(t_a, t_b), np.maximum(t_a, t_b)
    # A direction component of 0: inside that slab for all t, or for none.
    in_slab = (lo <= origin) & (origin <= hi)
    parallel = u == 0
    near = np.where(parallel, np.where(in_slab, -np.inf, np.inf), near)
    far = np.where(parallel, np.where(in_slab, np.inf, -np.inf), far)
    enter = np.maximum(0.0, near.max(axis=1, initial=-np.inf))
    leave = np.minimum(max_distance, far.min(axis=1, initial=np.inf))
    hit = np.flatnonzero((enter <= leave) & (enter < np.inf))
    order = np.lexsort((hit, enter[hit]))
    return hit[order], enter[hit][order]


def assert_query(method, lo, hi, box_lo, box_hi, **options):
    found = query(method, lo, hi, box_lo, box_hi, **options)
    assert found.dtype == np.intp and found.ndim == 1
    np.testing.assert_array_equal(found, reference_query(lo, hi, box_lo, box_hi))
    return found


def assert_raycast(method, lo, hi, origin, direction, max_distance, **options):
    found, t_enter = raycast(method, lo, hi, origin, direction, max_distance, **options)
    assert found.dtype == np.intp and t_enter.dtype == np.float64
    assert found.shape == t_enter.shape and found.ndim == 1
    expected, expected_t = reference_raycast(lo, hi, origin, direction, max_distance)
    np.testing.assert_array_equal(found, expected)
    np.testing.assert_allclose(t_enter, expected_t, rtol=1e-12, atol=0)
    return found, t_enter


def boxes(rows):
    """lo, hi from rows (x0, y0, x1, y1)."""
    table = np.array(rows, float).reshape(-1, 4)
    return table[:, :2].copy(), table[:, 2:].copy()


def lattice(rows=4, size=1.0, gap=0.0):
    """A rows x rows lattice of squares; with gap 0 neighbours share edges."""
    x, y = np.meshgrid(np.arange(rows) * (size + gap), np.arange(rows) * (size + gap))
    lo = np.column_stack((x.ravel(), y.ravel()))
    return lo, lo + size


# ------------------------------------------------------- property tests

component = st.one_of(st.integers(-3, 3).map(float), st.floats(-1, 1, allow_nan=False))
direction = st.tuples(component, component).filter(lambda d: d != (0.0, 0.0))
max_distance = st.one_of(st.just(0.0), st.just(math.inf), st.integers(0, 60).map(float),
                         st.floats(0, 300, allow_nan=False))


@settings(max_examples=60, deadline=None)
@given(scene=box_arrays(), corner=st.tuples(coordinate, coordinate),
       size=st.tuples(extent, extent), data=st.data())
def test_random_queries_match_reference(method, scene, corner, size, data):
    box_lo = np.array(corner)
    assert_query(method, *scene, box_lo, box_lo + size, **data.draw(OPTIONS[method]))


@settings(max_examples=60, deadline=None)
@given(scene=box_arrays(), origin=st.tuples(coordinate, coordinate), direction=direction,
       max_distance=max_distance, data=st.data())
def test_random_rays_match_reference(method, scene, origin, direction, max_distance, data):
    assert_raycast(method, *scene, origin, direction, max_distance,
                   **data.draw(OPTIONS[method]))


def test_random_scene_far_from_the_origin(method):
    """1e6 offsets: the slab arithmetic and the grid's cell edges round more."""
    rng = np.random.default_rng(1)
    lo = 1e6 + rng.uniform(0, 50, (300, 2))
    hi = lo + rng.choice([0.0, 0.5, 1.0, 2.5], (300, 2))
    for _ in range(20):
        origin = 1e6 + rng.uniform(-10, 60, 2)
        assert_raycast(method, lo, hi, origin, rng.normal(size=2), rng.choice([5.0, 40.0, np.inf]))
        box_lo = 1e6 + rng.uniform(0, 50, 2)
        assert_query(method, lo, hi, box_lo, box_lo + rng.uniform(0, 5, 2))


# ----------------------------------------------------------- queries

@pytest.mark.parametrize("n", [0, 1])
def test_query_on_zero_and_one_box(method, n):
    lo, hi = np.zeros((n, 2)), np.ones((n, 2))
    assert_query(method, lo, hi, [0.5, 0.5], [2.0, 2.0])
    assert_query(method, lo, hi, [3.0, 3.0], [4.0, 4.0])
    phase = make(method)
    found = phase.query(lo, hi, [0.5, 0.5], [2.0, 2.0])
    assert found.shape == (n,) and phase.stats["visited"] >= 0
    if n == 0:
        assert phase.stats["visited"] == 0


def test_query_duplicate_boxes(method):
    lo, hi = np.zeros((25, 2)), np.ones((25, 2))
    assert query(method, lo, hi, [0.5, 0.5], [0.6, 0.6]).tolist() == list(range(25))
    assert query(method, lo, hi, [1.0, 1.0], [2.0, 2.0]).tolist() == list(range(25))  # a corner
    assert query(method, lo, hi, [1.5, 0.0], [2.0, 1.0]).size == 0


def test_query_box_touching_boxes_exactly(method):
    lo, hi = lattice(rows=4)  # box 5 is [1, 2] x [1, 2]
    found = assert_query(method, lo, hi, [1.0, 1.0], [2.0, 2.0])
    assert found.tolist() == [0, 1, 2, 4, 5, 6, 8, 9, 10]  # edges and corners count
    assert assert_query(method, lo, hi, [4.0, 1.5], [5.0, 1.5]).tolist() == [7]  # right edge
    assert assert_query(method, lo, hi, [4.0, 4.0], [4.0, 4.0]).tolist() == [15]  # a point


def test_query_degenerate_boxes(method):
    # Points, and segments of zero width or height.
    lo, hi = boxes([[1, 1, 1, 1], [2, 0, 2, 3], [0, 2, 3, 2], [5, 5, 5, 5], [1, 1, 1, 1]])
    assert assert_query(method, lo, hi, [1, 1], [1, 1]).tolist() == [0, 4]
    assert assert_query(method, lo, hi, [2, 2], [2, 2]).tolist() == [1, 2]
    assert assert_query(method, lo, hi, [0, 0], [10, 10]).tolist() == [0, 1, 2, 3, 4]
    assert assert_query(method, lo, hi, [3.5, 3.5], [4.9, 6]).size == 0


def test_query_and_ray_on_a_segment_narrower_than_any_normal_float(method):
    """A point and a segment 2.2e-311 tall on it: the grid's default cells were as narrow, 1 /
    cell_size overflowed, and its query read cells outside its arrays (the process crashed)."""
    lo, hi = np.zeros((2, 2)), np.array([[0.0, 0.0], [0.0, 2.2250738585e-311]])
    assert assert_query(method, lo, hi, [0, 0], [0, 0]).tolist() == [0, 1]
    assert assert_raycast(method, lo, hi, [-1, 0], [1, 0], 5.0)[0].tolist() == [0, 1]


def test_query_around_a_large_box(method):
    rng = np.random.default_rng(2)
    lo = np.vstack(([[-50.0, -50.0]], rng.uniform(0, 100, (200, 2))))
    hi = np.vstack(([[150.0, 150.0]], lo[1:] + 1.0))
    found = assert_query(method, lo, hi, [60, 60], [61, 61])
    assert 0 in found


def test_query_options_pass_through():
    lo, hi = lattice(rows=10, gap=0.5)
    for method, options in [("grid", {"cell_size": 0.3}), ("kdtree", {"leaf_size": 1}),
                            ("kdtree", {"max_depth": 0}), ("bvh", {"leaf_size": 7})]:
        assert_query(method, lo, hi, [2.0, 2.0], [6.0, 4.0], **options)
        assert_raycast(method, lo, hi, [-1.0, 0.2], [3.0, 1.0], 20.0, **options)


# -------------------------------------------------------------- rays

@pytest.mark.parametrize("n", [0, 1])
def test_ray_on_zero_and_one_box(method, n):
    lo, hi = np.zeros((n, 2)), np.ones((n, 2))
    found, t_enter = assert_raycast(method, lo, hi, [-1.0, 0.5], [1.0, 0.0], 10.0)
    assert found.shape == t_enter.shape == (n,)
    if n:
        assert t_enter[0] == 1.0
    assert_raycast(method, lo, hi, [-1.0, 5.0], [1.0, 0.0], 10.0)  # passes above


def test_ray_through_duplicate_boxes(method):
    lo, hi = np.zeros((25, 2)), np.ones((25, 2))
    found, t_enter = assert_raycast(method, lo, hi, [-2.0, 0.5], [1.0, 0.0], np.inf)
    assert found.tolist() == list(range(25)) and np.all(t_enter == 2.0)  # ties by index


@pytest.mark.parametrize("origin, direction", [
    ([-1.0, 1.0], [1.0, 0.0]),    # along the edge y = 1 shared by two rows
    ([5.0, 1.0], [-1.0, 0.0]),    # the same edge, travelling left
    ([2.0, -1.0], [0.0, 1.0]),    # along the edge x = 2 shared by two columns
    ([2.0, 5.0], [0.0, -2.0]),    # the same edge, travelling down
    ([4.0, -1.0], [0.0, 1.0]),    # along the outer right edge of the lattice
    ([-1.0, 0.0], [1.0, 0.0]),    # along the outer bottom edge
])
def test_ray_along_box_edges_touches(method, origin, direction):
    lo, hi = lattice(rows=4)
    found, _ = assert_raycast(method, lo, hi, origin, direction, np.inf)
    assert len(found) in (4, 8)  # one row or column of boxes on each side of the line


def test_ray_starting_inside_a_box(method):
    lo, hi = lattice(rows=4, gap=1.0)  # box 5 is [2, 3] x [2, 3]
    found, t_enter = assert_raycast(method, lo, hi, [2.5, 2.5], [1.0, 0.0], np.inf)
    assert found.tolist() == [5, 6, 7] and t_enter.tolist() == [0.0, 1.5, 3.5]
    found, t_enter = assert_raycast(method, lo, hi, [2.0, 2.0], [-1.0, -1.0], np.inf)
    assert found.tolist() == [5, 0] and t_enter[0] == 0.0  # from the corner, through a corner


def test_max_distance_exactly_at_a_face_counts(method):
    lo, hi = boxes([[5, 0, 6, 1], [7, 0, 8, 1]])
    assert assert_raycast(method, lo, hi, [0, 0.5], [1, 0], 5.0)[0].tolist() == [0]
    assert assert_raycast(method, lo, hi, [0, 0.5], [1, 0], np.nextafter(5.0, 0))[0].size == 0
    # Along a diagonal into the corner (3, 3) of a box, at the distance the
    # slab arithmetic gives for it: exactly there counts, a hair short does not.
    lo, hi = boxes([[3, 3, 4, 4]])
    corner = 3.0 / (1.0 / math.hypot(1.0, 1.0))
    assert assert_raycast(method, lo, hi, [0, 0], [1, 1], corner)[1].tolist() == [corner]
    assert assert_raycast(method, lo, hi, [0, 0], [1, 1], np.nextafter(corner, 0))[0].size == 0


def test_max_distance_zero_hits_only_boxes_at_the_origin(method):
    lo, hi = lattice(rows=4)
    found, t_enter = assert_raycast(method, lo, hi, [1.0, 1.0], [1.0, 0.3], 0.0)
    assert found.tolist() == [0, 1, 4, 5] and np.all(t_enter == 0.0)
    assert assert_raycast(method, lo, hi, [-1.0, 1.0], [1.0, 0.0], 0.0)[0].size == 0


def test_infinite_max_distance(method):
    lo, hi = lattice(rows=6, gap=1.0)
    found, t_enter = assert_raycast(method, lo, hi, [-100.0, 0.5], [1.0, 0.0], np.inf)
    assert found.tolist() == [0, 1, 2, 3, 4, 5]
    assert_raycast(method, lo, hi, [0.5, -1e9], [0.01, 1.0], np.inf)


def test_diagonal_ray_through_corners(method):
    lo, hi = lattice(rows=4)  # the diagonal y = x passes exactly through lattice corners
    found, t_enter = assert_raycast(method, lo, hi, [-1.0, -1.0], [1.0, 1.0], np.inf)
    assert set(found) == {0, 1, 4, 5, 6, 9, 10, 11, 14, 15}  # corner-touching boxes count
    # x + y = 4 from the top-left corner: boxes (ix, iy) with 2 <= ix + iy <= 4.
    found, _ = assert_raycast(method, lo, hi, [0.0, 4.0], [1.0, -1.0], np.inf)
    assert set(found) == {2, 3, 5, 6, 7, 8, 9, 10, 12, 13}


def test_ray_through_degenerate_boxes(method):
    lo, hi = boxes([[1, 1, 1, 1], [2, 0, 2, 3], [0, 2, 3, 2], [3, 3, 3, 3], [1, 1, 1, 1]])
    found, t_enter = assert_raycast(method, lo, hi, [0, 0], [1, 1], np.inf)
    assert found.tolist() == [0, 4, 1, 2, 3]
    found, _ = assert_raycast(method, lo, hi, [2, -5], [0, 1], np.inf)  # along segment 1
    assert found.tolist() == [1, 2]


def test_rays_at_large_coordinates(method):
    lo, hi = lattice(rows=5)
    lo, hi = lo + 1e6, hi + 1e6
    assert_raycast(method, lo, hi, [1e6 - 1, 1e6 + 1], [1.0, 0.0], np.inf)
    found, _ = assert_raycast(method, lo, hi, [1e6 - 1, 1e6 - 1], [1.0, 1.0], np.inf)
    assert {0, 6, 12, 18, 24} <= set(found)
    assert_raycast(method, lo, hi, [1e6 + 2.5, 1e6 + 0.5], [-0.3, 0.7], 2.0)


# --------------------------------------------------- what the work costs

def test_visited_counts_show_the_pruning(method):
    rng = np.random.default_rng(3)
    n = 2000
    lo = rng.uniform(0, 200, (n, 2))
    hi = lo + rng.uniform(0.5, 1.5, (n, 2))
    phase = make(method)
    found = phase.query(lo, hi, [100.0, 100.0], [103.0, 103.0])
    np.testing.assert_array_equal(found, reference_query(lo, hi, [100, 100], [103, 103]))
    query_visited = phase.stats["visited"]
    found, _ = phase.raycast(lo, hi, [100.0, 100.0], [1.0, 0.5], 6.0)
    np.testing.assert_array_equal(found, reference_raycast(lo, hi, [100, 100], [1, 0.5], 6.0)[0])
    ray_visited = phase.stats["visited"]
    if method == "brute":
        assert query_visited == ray_visited == n
    else:
        assert query_visited < n / 10 and ray_visited < n / 10, (query_visited, ray_visited)


# ------------------------------------------------------------ bad input

@pytest.mark.parametrize("origin, direction, max_distance, message", [
    ([0, 0], [0, 0], 1.0, "ray direction must be non-zero"),
    ([np.nan, 0], [1, 0], 1.0, "ray origin must be finite"),
    ([0, np.inf], [1, 0], 1.0, "ray origin must be finite"),
    ([0, 0], [np.nan, 1], 1.0, "ray direction must be finite"),
    ([0, 0], [1, 0], -1.0, "max_distance must be >= 0"),
    ([0, 0], [1, 0], np.nan, "max_distance must be >= 0"),
    ([0, 0], [1, 0], "far", "max_distance must be a number"),
    ([0, 0, 0], [1, 0], 1.0, "ray origin and direction must each be two numbers"),
])
def test_bad_rays(method, origin, direction, max_distance, message):
    lo, hi = lattice(rows=2)
    for n in (0, len(lo)):
        with pytest.raises(ValueError, match=message) as error:
            raycast(method, lo[:n], hi[:n], origin, direction, max_distance)
        assert "\n" not in str(error.value)


@pytest.mark.parametrize("box_lo, box_hi", [
    ([0, 0], [np.nan, 1]), ([0, -np.inf], [1, 1]), ([2, 0], [1, 1]), ([0, 0, 0], [1, 1, 1]),
])
def test_bad_query_boxes(method, box_lo, box_hi):
    lo, hi = lattice(rows=2)
    with pytest.raises(ValueError):
        query(method, lo, hi, box_lo, box_hi)


def test_bad_boxes_are_refused(method):
    with pytest.raises(ValueError):
        query(method, [[0, 0]], [[np.nan, 1]], [0, 0], [1, 1])
    with pytest.raises(ValueError):
        raycast(method, [[2, 0]], [[1, 1]], [0, 0], [1, 0], 1.0)
