"""Broad phase: every method against a plain numpy all-pairs reference.

Like scipy's test_kdtree: one fixture runs each test on every method. The
contract: (k, 2) intp pairs, i < j, sorted, unique, containing every pair of
overlapping boxes (touching counts); extra candidates are allowed.
"""

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st
from strategies import OPTIONS, box_arrays

from collisim.broadphase import PROTOCOL, describe, find_pairs, make


@pytest.fixture(scope="module", params=PROTOCOL)
def method(request):
    return request.param


# ---------------------------------------------------------------- helpers

def overlaps(lo, hi, i, j):
    """Vectorised: do boxes i[k] and j[k] overlap (touching counts)?"""
    return np.all((lo[i] <= hi[j]) & (lo[j] <= hi[i]), axis=1)


def reference_pairs(lo, hi):
    """All overlapping pairs by testing every pair: (k, 2), sorted."""
    i, j = np.triu_indices(len(lo), k=1)
    keep = overlaps(lo, hi, i, j)
    return np.stack((i[keep], j[keep]), axis=1).astype(np.intp)


def truly_overlapping(lo, hi, pairs):
    """Keep only the candidate pairs whose boxes really overlap."""
    return pairs[overlaps(lo, hi, pairs[:, 0], pairs[:, 1])]


def as_set(pairs):
    return set(map(tuple, pairs.tolist()))


def assert_contract(pairs, lo, hi):
    """Shape, dtype, order, uniqueness, and completeness of a result."""
    assert pairs.dtype == np.intp
    assert pairs.ndim == 2 and pairs.shape[1] == 2
    assert np.all(pairs[:, 0] < pairs[:, 1])
    keys = pairs[:, 0].astype(np.int64) * max(len(lo), 1) + pairs[:, 1]
    assert np.all(np.diff(keys) > 0), "pairs must be sorted and unique"
    if len(pairs):
        assert pairs.min() >= 0 and pairs.max() < len(lo)
    missing = as_set(reference_pairs(lo, hi)) - as_set(pairs)
    assert not missing, f"overlapping pairs not reported: {sorted(missing)[:5]}"


def assert_matches_reference(method, lo, hi, **options):
    pairs = find_pairs(method, lo, hi, **options)
    assert_contract(pairs, lo, hi)
    np.testing.assert_array_equal(truly_overlapping(lo, hi, pairs), reference_pairs(lo, hi))
    return pairs


def circles(centres, radii):
    centres = np.asarray(centres, float)
    radii = np.broadcast_to(np.asarray(radii, float), len(centres))[:, None]
    return centres - radii, centres + radii


def gas(n, side, seed, radii=(1.0, 1.5, 2.0)):
    rng = np.random.default_rng(seed)
    return circles(rng.uniform(0, side, (n, 2)), rng.choice(radii, n))


# ------------------------------------------------------- property tests



@settings(max_examples=60, deadline=None)
@given(boxes=box_arrays())
def test_random_boxes_match_brute_force(method, boxes):
    assert_matches_reference(method, *boxes)


@settings(max_examples=60, deadline=None)
@given(boxes=box_arrays(), data=st.data())
def test_random_boxes_with_random_options(method, boxes, data):
    assert_matches_reference(method, *boxes, **data.draw(OPTIONS[method]))


# ----------------------------------------------------- degenerate inputs

def lattice_of_touching_circles(rows=8):
    """Radius-1 circles 2 apart: neighbours' boxes share edges, diagonal ones corners."""
    x, y = np.meshgrid(np.arange(rows) * 2.0, np.arange(rows) * 2.0)
    return circles(np.column_stack((x.ravel(), y.ravel())), 1.0)


def two_dense_clusters():
    rng = np.random.default_rng(3)
    centres = np.concatenate((rng.normal(0, 2, (60, 2)), rng.normal(100, 2, (60, 2))))
    return circles(centres, 1.0)


def radii_spanning_100x():
    rng = np.random.default_rng(4)
    return circles(rng.uniform(0, 200, (150, 2)), 10 ** rng.uniform(-1, 1, 150))


def all_overlapping_on_the_sweep_axis():
    """Boxes 30 wide whose centres spread 10 along x and 4 along y: x is the sweep axis
    (the larger spread) and every box overlaps every other on it, so a sweep's forward walk
    meets all n^2 / 2 pairs and only the other axis prunes."""
    rng = np.random.default_rng(6)
    centres = np.column_stack((rng.uniform(0, 10, 300), rng.uniform(0, 4, 300)))
    return centres - [15.0, 0.1], centres + [15.0, 0.1]


def tall_thin_column_with_duplicates():
    """A column one box wide and 400 tall, each box present twice or three times over
    (equal keys on every axis, in scattered index order)."""
    rng = np.random.default_rng(7)
    centres = np.column_stack((rng.uniform(0, 0.5, 150), rng.uniform(0, 400, 150)))
    centres = centres[rng.permutation(np.r_[np.arange(150), np.arange(150), np.arange(50)])]
    return circles(centres, 1.0)


DEGENERATE = {
    "all on one x": circles(np.column_stack((np.zeros(40), np.linspace(0, 50, 40))), 1.0),
    "identical boxes": (np.zeros((25, 2)), np.ones((25, 2))),
    "identical points": (np.full((25, 2), 3.0), np.full((25, 2), 3.0)),
    "touching lattice": lattice_of_touching_circles(),
    "two dense clusters": two_dense_clusters(),
    "radii spanning 100x": radii_spanning_100x(),
    "all overlapping on the sweep axis": all_overlapping_on_the_sweep_axis(),
    "tall thin column with duplicates": tall_thin_column_with_duplicates(),
    "one giant among small": circles(np.vstack(([50.0, 50.0], gas(80, 100, 5)[0] + 1)),
                                     np.r_[40.0, np.ones(80)]),
}


@pytest.mark.parametrize("case", DEGENERATE)
def test_degenerate_inputs(method, case):
    assert_matches_reference(method, *DEGENERATE[case])


def test_touching_counts_as_overlapping(method):
    lo, hi = lattice_of_touching_circles(rows=3)
    pairs = as_set(find_pairs(method, lo, hi))
    assert {(0, 1), (0, 3), (0, 4), (1, 3)} <= pairs  # edge and corner contacts


def test_particle_larger_than_a_grid_cell(method):
    lo, hi = circles([[0, 0], [3, 0], [-3, 2], [10, 10]], [5.0, 0.2, 0.2, 0.2])
    options = {"cell_size": 0.5} if method == "grid" else {}
    pairs = assert_matches_reference(method, lo, hi, **options)
    assert as_set(truly_overlapping(lo, hi, pairs)) == {(0, 1), (0, 2)}


@pytest.mark.parametrize("n", [0, 1])
def test_fewer_than_two_boxes_give_no_pairs(method, n):
    pairs = find_pairs(method, np.zeros((n, 2)), np.ones((n, 2)))
    assert pairs.shape == (0, 2) and pairs.dtype == np.intp


def test_two_boxes(method):
    lo, hi = circles([[0, 0], [1, 0]], 1.0)
    assert find_pairs(method, lo, hi).tolist() == [[0, 1]]
    lo, hi = circles([[0, 0], [5, 0]], 1.0)
    assert find_pairs(method, lo, hi).shape == (0, 2)


def test_a_point_on_a_segment_narrower_than_any_normal_float(method):
    """The example hypothesis found (box_arrays draws subnormal extents): a point at the
    origin and a segment 2.2e-311 tall from it. The grid's default cells were as narrow as
    the segment, 1 / cell_size overflowed to inf, the grid's shape to garbage, and the
    touching pair went unreported."""
    lo = np.zeros((2, 2))
    hi = np.array([[0.0, 0.0], [0.0, 2.2250738585e-311]])
    assert_matches_reference(method, lo, hi)
    assert find_pairs(method, lo, hi).tolist() == [[0, 1]]


@pytest.mark.parametrize("cell_size", [0.3, 1.0, 2.5, 7.0, 1000.0])
def test_grid_with_explicit_cell_size(cell_size):
    lo, hi = gas(300, 60, seed=6)
    assert_matches_reference("grid", lo, hi, cell_size=cell_size)


def test_grid_reports_its_memory():
    grid = make("grid")
    grid.pairs(*gas(500, 80, seed=7))
    assert grid.stats["memory_bytes"] > 0 and grid.stats["cell_size"] > 0


@pytest.mark.parametrize("options", [{"max_depth": 0}, {"max_depth": 1}, {"leaf_size": 1},
                                     {"leaf_size": 3, "max_depth": 4}, {"leaf_size": 1000}])
def test_kdtree_termination_options(options):
    lo, hi = gas(300, 60, seed=8)
    kdtree = make("kdtree", **options)
    pairs = kdtree.pairs(lo, hi)
    np.testing.assert_array_equal(truly_overlapping(lo, hi, pairs), reference_pairs(lo, hi))
    assert kdtree.stats["depth"] <= options.get("max_depth", 32)


def test_kdtree_stops_when_no_split_helps():
    # Two overlapping circles straddle any line between them: the root stays a leaf.
    lo, hi = circles([[0, 0], [1, 0.5]], 1.0)
    kdtree = make("kdtree", leaf_size=1)
    assert kdtree.pairs(lo, hi).tolist() == [[0, 1]]
    assert kdtree.stats["nodes"] == 1
    picture = describe("kdtree", lo, hi, leaf_size=1)
    assert picture["splits"] == [] and len(picture["leaves"]) == 1


@pytest.mark.parametrize("leaf_size", [1, 2, 5])
def test_bvh_leaf_sizes(leaf_size):
    lo, hi = gas(300, 60, seed=9)
    bvh = make("bvh", leaf_size=leaf_size)
    pairs = bvh.pairs(lo, hi)
    np.testing.assert_array_equal(truly_overlapping(lo, hi, pairs), reference_pairs(lo, hi))
    assert bvh.stats["nodes"] <= 2 * len(lo) - 1


# ------------------------------------------- sweep and prune across frames

def test_sweep_prune_keeps_up_across_frames():
    rng = np.random.default_rng(10)
    centres, radii = rng.uniform(0, 60, (300, 2)), rng.choice([1.0, 1.5, 2.0], 300)
    sweep = make("sweep_prune")
    for frame in range(30):
        centres = centres + rng.normal(0, 0.2, centres.shape)  # small motion
        if frame % 7 == 3:  # some large jumps
            jumpers = rng.choice(len(centres), 15, replace=False)
            centres[jumpers] = rng.uniform(0, 60, (15, 2))
        if frame == 15:  # particles leave: the order must be rebuilt
            centres, radii = centres[20:], radii[20:]
        if frame == 22:  # stretch the other axis: the sweep axis changes, so re-sort
            centres[:, 1 - sweep.stats["axis"]] *= 3.0
        lo, hi = circles(centres, radii)
        pairs = sweep.pairs(lo, hi)
        assert_contract(pairs, lo, hi)
        np.testing.assert_array_equal(truly_overlapping(lo, hi, pairs), reference_pairs(lo, hi))
        if frame in (0, 15, 22):
            assert sweep.stats["resorted"]
        elif frame % 7 != 3:
            assert not sweep.stats["resorted"]


def interval_pairs(lo, hi, axis):
    """Every pair whose intervals on `axis` overlap (touching counts), by testing every pair."""
    i, j = np.triu_indices(len(lo), k=1)
    keep = (lo[i, axis] <= hi[j, axis]) & (lo[j, axis] <= hi[i, axis])
    return np.stack((i[keep], j[keep]), axis=1).astype(np.intp)


@pytest.mark.parametrize("axis", [0, 1])
def test_sweep_prune_reports_every_overlap_on_its_axis_as_the_video_does(axis):
    """Not only the pairs whose boxes overlap: every pair whose intervals meet on the sweep axis
    (the axis of larger spread: the one stretched here), the other axis never looked at."""
    lo, hi = gas(300, 60, seed=12)
    stretch = np.where(np.arange(2) == axis, 3.0, 1.0)
    lo, hi = lo * stretch, hi * stretch
    sweep = make("sweep_prune")
    pairs = sweep.pairs(lo, hi)
    assert sweep.stats["axis"] == axis
    np.testing.assert_array_equal(pairs, interval_pairs(lo, hi, axis))
    assert len(pairs) > len(reference_pairs(lo, hi))     # more than the overlapping boxes


def test_kdtree_alternates_its_split_axis_by_depth_as_the_video_does():
    """x at the root, y below, x below that: each split on its depth's axis (for a gas where
    every median split helps on that axis)."""
    lo, hi = gas(300, 60, seed=13, radii=(0.01,))   # small: no box straddles a median
    splits = describe("kdtree", lo, hi, leaf_size=2)["splits"]
    assert {depth for *_, depth in splits} >= set(range(6))
    assert [axis for axis, *_ in splits] == [depth % 2 for *_, depth in splits]


def test_kdtree_splits_on_the_other_axis_when_its_depths_cannot_help():
    """A column of boxes all straddling the median on x: the root splits on y, not one leaf of
    every box."""
    lo, hi = circles(np.column_stack([np.full(40, 5.0), np.arange(40.0) * 3]), 1.0)
    picture = describe("kdtree", lo, hi, leaf_size=2)
    assert picture["splits"][0][0] == 1 and max(len(leaf) for leaf in picture["leaves"]) <= 2


# ---------------------------------------------------------------- describe

SIX = circles([[1, 1], [2.2, 1.6], [5, 5], [5.6, 4], [8, 2], [8.4, 2.5]], 0.8)
PICTURE_OPTIONS = {"kdtree": {"leaf_size": 1}, "bvh": {"leaf_size": 1}}


def test_describe_pairs_agree_with_find_pairs(method):
    options = PICTURE_OPTIONS.get(method, {})
    picture = describe(method, *SIX, **options)
    np.testing.assert_array_equal(picture["pairs"], find_pairs(method, *SIX, **options))


def test_describe_sweep_prune():
    lo, hi = SIX
    picture = describe("sweep_prune", lo, hi)
    axis, order = picture["axis"], picture["order"]
    assert sorted(order) == list(range(6))
    assert np.all(np.diff(lo[order, axis]) >= 0)
    np.testing.assert_array_equal(picture["intervals"], np.column_stack((lo[:, axis], hi[:, axis])))
    assert [step[-1] for step in picture["active_steps"]] == list(order)


def test_describe_grid():
    picture = describe("grid", *SIX, cell_size=2.0)
    assert picture["counts"].shape == picture["shape"]
    assert picture["counts"].sum() >= 6 and picture["cell_size"] == 2.0
    assert picture["origin"].shape == (2,)


def test_describe_kdtree():
    picture = describe("kdtree", *SIX, leaf_size=1)
    splits, leaves = picture["splits"], picture["leaves"]
    assert len(leaves) == len(splits) + 1  # a binary tree
    assert 2 <= len(splits) <= 6
    assert set(np.concatenate(leaves)) == set(range(6))  # straddlers may repeat
    for axis, value, node_lo, node_hi, depth in splits:
        assert axis in (0, 1) and node_lo[axis] <= value <= node_hi[axis]


def test_describe_bvh_leaves_partition_the_boxes():
    picture = describe("bvh", *SIX, leaf_size=1)
    leaves = picture["leaves"]
    assert sorted(np.concatenate(leaves)) == list(range(6))  # each box in exactly one leaf
    assert len(picture["nodes"]) == 2 * len(leaves) - 1
    assert sum(is_leaf for *_, is_leaf in picture["nodes"]) == len(leaves)
    root_lo, root_hi, root_depth, _ = picture["nodes"][0]
    np.testing.assert_array_equal(root_lo, SIX[0].min(axis=0))
    np.testing.assert_array_equal(root_hi, SIX[1].max(axis=0))


# --------------------------------------------------- determinism and errors

def test_same_input_same_bytes(method):
    lo, hi = gas(2000, 150, seed=11)
    lo, hi = np.round(lo), np.round(hi)  # plenty of ties
    first = find_pairs(method, lo, hi)
    phase = make(method)
    assert first.tobytes() == phase.pairs(lo, hi).tobytes() == phase.pairs(lo, hi).tobytes()
    assert phase.stats["candidates"] == len(first)


def test_unknown_broad_phase():
    with pytest.raises(ValueError, match="^unknown broad phase 'x'; choose one of: "
                                         "brute, sweep_prune, grid, kdtree, bvh, cells$"):
        find_pairs("x", np.zeros((2, 2)), np.ones((2, 2)))


@pytest.mark.parametrize("method, options", [
    ("brute", {"cell_size": 1.0}), ("grid", {"leaf_size": 2}), ("grid", {"cell_size": 0}),
    ("grid", {"cell_size": -1.0}), ("grid", {"cell_size": float("nan")}), ("grid", {"cell_size": "big"}),
    ("kdtree", {"leaf_size": 0}), ("kdtree", {"leaf_size": 1.5}), ("kdtree", {"max_depth": -1}),
    ("bvh", {"leaf_size": True}),
])
def test_bad_options(method, options):
    with pytest.raises(ValueError):
        make(method, **options)


@pytest.mark.parametrize("lo, hi", [
    ([[0, 0], [np.nan, 0]], [[1, 1], [1, 1]]),
    ([[0, 0], [0, 0]], [[1, np.inf], [1, 1]]),
    ([[0, 0], [2, 0]], [[1, 1], [1, 1]]),  # lo > hi
    ([[0, 0, 0]], [[1, 1, 1]]),
    ([[0, 0]], [[1, 1], [2, 2]]),
])
def test_bad_boxes(method, lo, hi):
    with pytest.raises(ValueError):
        find_pairs(method, np.array(lo, float), np.array(hi, float))


def test_grid_refuses_an_absurd_number_of_cells():
    with pytest.raises(ValueError, match="cell_size"):
        find_pairs("grid", np.array([[0.0, 0.0], [1e6, 1e6]]), np.array([[1.0, 1.0], [1e6, 1e6]]),
                   cell_size=1e-3)


@pytest.mark.parametrize("cell_size", [1e-300, 1e-320])
def test_grid_refuses_a_cell_size_whose_grid_overflows(cell_size):
    """1e300 cells a side (or 1 / cell_size = inf) once wrapped around int64 to an empty grid,
    which reported no pairs at all."""
    with pytest.raises(ValueError, match="cell_size"):
        find_pairs("grid", np.array([[0.0, 0.0], [1.0, 1.0]]), np.array([[2.0, 2.0], [3.0, 3.0]]),
                   cell_size=cell_size)


@pytest.mark.parametrize("values", [
    np.random.default_rng(12).normal(size=500),
    np.round(np.random.default_rng(13).uniform(0, 5, 500)),  # long runs of ties
    np.arange(300.0), np.arange(300.0)[::-1].copy(), np.full(200, 2.0),
])
def test_select_smallest_is_a_partial_sort(values):
    """The trees' median finder (nth_element) against numpy's sort, at every rank."""
    from collisim.broadphase._common import select_smallest

    expected = np.sort(values)
    for k in range(0, len(values), 37):
        work = values.copy()
        select_smallest(work, len(work), k)
        assert work[k] == expected[k]
        assert np.all(work[:k] <= work[k]) and np.all(work[k + 1:] >= work[k])
        np.testing.assert_array_equal(np.sort(work), expected)


@pytest.mark.parametrize("values", [
    np.random.default_rng(12).normal(size=500), np.round(np.random.default_rng(13).uniform(0, 5, 500)),
    np.arange(300.0), np.arange(300.0)[::-1].copy(), np.full(200, 2.0), np.array([1.0]), np.array([2.0, 1.0]),
])
def test_the_median_finders_fallback_sorts_a_run_as_numpy_does(values):
    """What the median finder sorts once quickselect stops converging (heapsort), on a run in
    the middle of the array, the values outside it left as they were."""
    from collisim.core.arrays import heap_sort

    work, first, end = values.copy(), len(values) // 5, len(values) - len(values) // 7
    heap_sort(work, first, end)
    np.testing.assert_array_equal(work[first:end], np.sort(values[first:end]))
    np.testing.assert_array_equal(work[:first], values[:first])
    np.testing.assert_array_equal(work[end:], values[end:])


@settings(max_examples=60, deadline=None)
@given(st.integers(2, 400), st.integers(0, 2000), st.integers(0, 2 ** 31))
def test_the_step_puts_any_broad_phases_pairs_in_canonical_order(n, count, seed):
    """Whatever order a broad phase finds its pairs in, the step treats them by (i, j): the order
    numpy's lexicographic sort gives."""
    from collisim.broadphase.step import sort_pairs

    rng = np.random.default_rng(seed)
    i, j = rng.integers(0, n, count), rng.integers(0, n, count)
    keep = i < j
    pairs = np.unique(np.column_stack([i[keep], j[keep]]), axis=0)   # each pair once, i < j
    shuffled = pairs[rng.permutation(len(pairs))].astype(np.intp)
    np.testing.assert_array_equal(sort_pairs(shuffled, n), pairs)
    np.testing.assert_array_equal(sort_pairs(pairs.astype(np.intp), n), pairs)
