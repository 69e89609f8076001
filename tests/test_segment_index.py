"""The static segment index against brute force.

The contract (collisim.statics.segment_index): a segment is registered in
exactly the grid cells it meets (closed cells), and a query returns, sorted and
unique, every segment that meets the query box (extra ones are allowed).

The reference is the separating-axis test for a segment against a closed
rectangle: they meet iff their bounding boxes overlap and the rectangle's
corners are not all strictly on one side of the segment's line. Most
coordinates are drawn on a 1/16 lattice (and cells are multiples of 1/16), so
every product in it is exact in float64 and the reference is exact: touching
at an end point, lying on a cell edge, and grazing a corner are decided exactly.
"""
import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings, strategies as st

from collisim.statics import SegmentIndex, build_segment_index, segments_near, segments_near_box

BOX = (0.0, 0.0, 100.0, 100.0)


# ---------------------------------------------------------------- reference

def meets_rect(segments, lo_x, lo_y, hi_x, hi_y):
    """(m,) bool: does each segment (m, 4) meet the closed rectangle? Vectorised over
    segments, or over rectangles if the bounds are arrays and segments is one row."""
    x0, y0, x1, y1 = (segments[..., k] for k in range(4))
    boxes_overlap = ((np.minimum(x0, x1) <= hi_x) & (np.maximum(x0, x1) >= lo_x)
                     & (np.minimum(y0, y1) <= hi_y) & (np.maximum(y0, y1) >= lo_y))
    dx, dy = x1 - x0, y1 - y0
    sides = [dx * (cy - y0) - dy * (cx - x0) for cx, cy in
             ((lo_x, lo_y), (hi_x, lo_y), (lo_x, hi_y), (hi_x, hi_y))]
    all_left = np.all([s > 0 for s in sides], axis=0)
    all_right = np.all([s < 0 for s in sides], axis=0)
    return boxes_overlap & ~all_left & ~all_right


def cells_meeting(index, segment):
    """Set of cell ids (cy * nx + cx) whose closed square meets the segment."""
    cy, cx = np.divmod(np.arange(index.nx * index.ny), index.nx)
    left, bottom = index.x0 + cx * index.cell, index.y0 + cy * index.cell
    hit = meets_rect(np.asarray(segment, float), left, bottom, left + index.cell, bottom + index.cell)
    return set(np.flatnonzero(hit).tolist())


def registered_cells(index):
    """For each segment, the set of cells it is registered in."""
    cell_of_entry = np.repeat(np.arange(index.nx * index.ny), np.diff(index.cell_start))
    return [set(cell_of_entry[index.cell_segments == s].tolist()) for s in range(len(index.mark))]


def check_csr(index):
    start = index.cell_start
    assert start.shape == (index.nx * index.ny + 1,) and start.dtype == np.int64
    assert start[0] == 0 and np.all(np.diff(start) >= 0) and start[-1] == len(index.cell_segments)
    for c in range(index.nx * index.ny):
        run = index.cell_segments[start[c]:start[c + 1]]
        assert np.all(np.diff(run) > 0), "each cell's list is ascending, without repeats"


# ---------------------------------------------------------------- random scenes

lattice = st.integers(-50 * 16, 150 * 16).map(lambda k: k / 16)  # in and around the box


@st.composite
def scenes(draw):
    """(segments (m, 4), cell or None): every awkward kind of segment."""
    cell = draw(st.sampled_from([None, 6.25, 10.0, 12.5, 3.0625]))
    rows = []
    for kind in draw(st.lists(st.sampled_from(["free", "long", "tiny", "point"]), max_size=30)):
        x, y = draw(lattice), draw(lattice)
        if kind == "free":
            rows.append((x, y, draw(lattice), draw(lattice)))
        elif kind == "long":  # corner to corner, sticking out of the box
            rows.append((x / 4 - 40, y, x / 4 + 140, draw(lattice)))
        elif kind == "tiny":
            a, b = draw(st.integers(-3, 3)), draw(st.integers(-3, 3))
            rows.append((x, y, x + a / 16, y + b / 16))
        else:  # zero length
            rows.append((x, y, x, y))
    segments = np.array(rows, float).reshape(-1, 4)
    if cell is not None:
        # Axis-aligned segments exactly on grid lines (the grid starts at the lower
        # left corner of the box and the segments, so those are known by now).
        ox = min(BOX[0], segments[:, [0, 2]].min(initial=BOX[0]))
        oy = min(BOX[1], segments[:, [1, 3]].min(initial=BOX[1]))
        for _ in range(draw(st.integers(0, 4))):
            k, a, b = draw(st.integers(0, 12)), draw(st.integers(0, 12)), draw(st.integers(0, 12))
            if draw(st.booleans()):
                rows.append((ox + k * cell, oy + a * cell, ox + k * cell, oy + b * cell))
            else:
                rows.append((ox + a * cell, oy + k * cell, ox + b * cell, oy + k * cell))
    if rows and draw(st.booleans()):  # exact duplicates
        rows += draw(st.lists(st.sampled_from(rows), max_size=3))
    return np.array(rows, float).reshape(-1, 4), cell


@st.composite
def query_boxes(draw, segments):
    """(lo_x, lo_y, hi_x, hi_y) boxes, some degenerate, some cornered on end points."""
    if len(segments) and draw(st.booleans()):
        s, end = draw(st.integers(0, len(segments) - 1)), draw(st.sampled_from([0, 2]))
        x, y = segments[s, end], segments[s, end + 1]
        if draw(st.booleans()):  # the end point is the box's upper right corner
            return x - draw(lattice) % 20, y - draw(lattice) % 20, x, y
        return x, y, x + draw(lattice) % 20, y + draw(lattice) % 20
    if draw(st.integers(0, 4)) == 0:  # general floats, far outside too
        x, y = draw(st.floats(-1e3, 1e3)), draw(st.floats(-1e3, 1e3))
        return x, y, x + draw(st.floats(0, 50)), y + draw(st.floats(0, 50))
    x, y = draw(lattice), draw(lattice)
    return x, y, x + draw(lattice) % 30, y + draw(lattice) % 30


# ---------------------------------------------------------------- against brute force

@settings(max_examples=80, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(data=st.data())
def test_random_scenes_against_brute_force(data):
    segments, cell = data.draw(scenes())
    index = build_segment_index(segments, BOX, cell)
    m = len(segments)
    assert isinstance(index, SegmentIndex) and index.mark.shape == (m,)
    check_csr(index)
    # The grid covers the box and every segment.
    assert index.x0 <= BOX[0] and index.y0 <= BOX[1]
    far_x, far_y = index.x0 + index.nx * index.cell, index.y0 + index.ny * index.cell
    assert far_x >= max(BOX[2], segments[:, [0, 2]].max(initial=0))  # closed cells
    assert far_y >= max(BOX[3], segments[:, [1, 3]].max(initial=0))
    if cell is not None:
        # Lattice coordinates and cells: the registration must be exactly right.
        for s, cells in enumerate(registered_cells(index)):
            assert cells == cells_meeting(index, segments[s]), f"segment {s} {segments[s]}"
    out = np.empty(m, np.int64)
    for _ in range(10):
        lo_x, lo_y, hi_x, hi_y = data.draw(query_boxes(segments))
        count = segments_near(index, lo_x, lo_y, hi_x, hi_y, out)
        found = out[:count]
        assert np.all(np.diff(found) > 0), "sorted and unique"
        assert np.all((found >= 0) & (found < m))
        expected = np.flatnonzero(meets_rect(segments, lo_x, lo_y, hi_x, hi_y))
        missing = np.setdiff1d(expected, found)
        assert missing.size == 0, f"box {(lo_x, lo_y, hi_x, hi_y)} misses segments {segments[missing]}"
        assert np.array_equal(segments_near_box(index, (lo_x, lo_y), (hi_x, hi_y)), found)


def test_segment_on_cell_edges_registers_in_both_neighbours():
    index = build_segment_index(np.array([[30.0, 5.0, 30.0, 25.0],   # on the line x = 30
                                          [30.0, 30.0, 30.0, 30.0],  # a point on a grid corner
                                          [0.0, 40.0, 100.0, 40.0]]), BOX, cell=10.0)
    cells = registered_cells(index)
    assert cells[0] == {cy * index.nx + cx for cx in (2, 3) for cy in (0, 1, 2)}
    assert cells[1] == {cy * index.nx + cx for cx in (2, 3) for cy in (2, 3)}
    assert cells[2] == {cy * index.nx + cx for cx in range(index.nx) for cy in (3, 4)}


def test_points_where_cell_index_and_cell_edges_round_apart():
    # floor((x - x0) / cell) and the edges x0 + k * cell are rounded separately, so a
    # point a few ulps from an edge can be "in cell k" by the first and outside its
    # square by the second. Such points must still be found by a query at themselves.
    x0, cell = -9.932126670142608, 0.3
    edges = x0 + np.arange(1, 1000) * cell
    near = np.concatenate([edges] + [np.nextafter(edges, edges + d) for d in (-1.0, 1.0)]
                          + [np.nextafter(np.nextafter(edges, edges + d), edges + d) for d in (-1.0, 1.0)])
    column = np.floor((near - x0) * (1.0 / cell))
    awkward = near[(near < x0 + column * cell) | (near > x0 + (column + 1) * cell)]
    assert len(awkward) > 10  # the case exists
    points = np.column_stack((awkward, np.full_like(awkward, 5.0), awkward, np.full_like(awkward, 5.0)))
    index = build_segment_index(points, (x0, 0.0, 300.0, 10.0), cell=cell)
    for s, x in enumerate(awkward):
        assert s in segments_near_box(index, (x, 5.0), (x, 5.0))


# ---------------------------------------------------------------- cost

@pytest.mark.parametrize("segment", [(0.0, 0.0, 1000.0, 1000.0), (0.0, 0.5, 1000.0, 999.3),
                                     (1000.0, 3.0, 0.0, 700.0)])
def test_long_diagonal_registers_along_its_length(segment):
    # 1000 x 1000 cells of side 1: the bounding box holds up to a million cells, the
    # line itself passes through at most 2 per unit of length (3 at exact corners).
    index = build_segment_index(np.array([segment]), (0.0, 0.0, 1000.0, 1000.0), cell=1.0)
    length_in_cells = abs(segment[2] - segment[0]) + abs(segment[3] - segment[1])
    entries = int(index.cell_start[-1])
    assert 0 < entries <= 1.5 * length_in_cells + 8
    assert set(registered_cells(index)[0]) == cells_meeting(index, segment)


def test_many_short_segments_give_few_candidates(rng):
    # 2000 short segments in a 100 x 100 box; bodies of radius 0.5 query their
    # bounding box: the candidates per body must stay O(1).
    m = 2000
    start = rng.uniform(0.0, 100.0, (m, 2))
    angle, length = rng.uniform(0.0, 2 * np.pi, m), rng.uniform(0.5, 3.0, m)
    segments = np.column_stack((start, start + length[:, None] * np.column_stack((np.cos(angle), np.sin(angle)))))
    index = build_segment_index(segments, BOX)
    assert index.nx * index.ny <= 4 * m + 64
    centres = rng.uniform(0.0, 100.0, (500, 2))
    out = np.empty(m, np.int64)
    counts = [segments_near(index, x - 0.5, y - 0.5, x + 0.5, y + 0.5, out) for x, y in centres]
    assert np.mean(counts) < 20
    for x, y in centres[:50]:  # and nothing is missed
        expected = np.flatnonzero(meets_rect(segments, x - 0.5, y - 0.5, x + 0.5, y + 0.5))
        assert np.isin(expected, segments_near_box(index, (x - 0.5, y - 0.5), (x + 0.5, y + 0.5))).all()


def test_default_cell_limits_the_grid():
    # A few far-apart points: the mean length (0) must not make a huge grid.
    points = np.array([[0.0, 0.0, 0.0, 0.0], [1e6, 1e6, 1e6, 1e6], [5.0, 5.0, 5.0, 5.0]])
    index = build_segment_index(points, BOX)
    assert index.nx * index.ny <= 4 * 3 + 64
    assert list(segments_near_box(index, (4.0, 4.0), (6.0, 6.0))) == [0, 2]  # cell-mates come along
    # Many tiny segments: never more than 4 million cells.
    tiny = np.repeat(np.array([[0.0, 0.0, 1e-6, 0.0], [1e4, 1e4, 1e4, 1e4 + 1e-6]]), 600_000, axis=0)
    index = build_segment_index(tiny, BOX)
    assert index.nx * index.ny <= 4_000_000
    with pytest.raises(ValueError):
        build_segment_index(points, BOX, cell=1.0)  # 10^12 cells


# ---------------------------------------------------------------- edge cases

def test_no_segments():
    index = build_segment_index(np.zeros((0, 4)), BOX)
    assert (index.nx, index.ny) == (1, 1) and list(index.cell_start) == [0, 0]
    assert segments_near_box(index, (10.0, 10.0), (20.0, 20.0)).shape == (0,)
    assert segments_near_box(index, (-1e9, -1e9), (-1e9, -1e9)).shape == (0,)


def test_one_segment():
    index = build_segment_index(np.array([[10.0, 10.0, 20.0, 30.0]]), BOX)
    check_csr(index)
    assert list(segments_near_box(index, (14.0, 19.0), (16.0, 21.0))) == [0]
    assert list(segments_near_box(index, (19.0, 29.0), (25.0, 35.0))) == [0]


def test_queries_far_outside_clamp_to_the_border():
    segments = np.array([[-5.0, 50.0, 5.0, 50.0],      # sticks out on the left
                         [50.0, 50.0, 60.0, 60.0],
                         [95.0, 99.0, 130.0, 99.0]])   # sticks out on the right
    index = build_segment_index(segments, BOX)
    assert index.x0 == -5.0
    # Far to the right: clamped onto the last column, where segment 2 ends (x = 130).
    assert 2 in segments_near_box(index, (1e6, 98.0), (2e6, 100.0))
    assert 0 not in segments_near_box(index, (1e6, 1e6), (2e6, 2e6))
    for lo, hi in [((-1e12, -1e12), (-1e11, -1e11)), ((1e12, -1e12), (1e12, 1e12)),
                   ((-np.inf, 0.0), (-np.inf, 1.0)), ((0.0, np.inf), (1.0, np.inf))]:
        found = segments_near_box(index, lo, hi)
        assert np.all(np.diff(found) > 0) and np.all((found >= 0) & (found < 3))
    # A box containing everything returns everything; stamps keep working after many queries.
    for _ in range(3):
        assert list(segments_near_box(index, (-1e9, -1e9), (1e9, 1e9))) == [0, 1, 2]
    assert index.stamp[0] >= 7


@pytest.mark.parametrize("n", [200, 40_000])
def test_circles_touching_segments_are_found_as_shapely_measures_them(n):
    # the start check's query (engine/start.py): every circle that touches a segment, through the index
    import shapely
    from collisim.narrowphase.statics import touching_segments
    rng = np.random.default_rng(n)
    segments = rng.uniform(0.0, 100.0, (150, 4))
    segments[:5, 2:] = segments[:5, :2]   # points: segments of no length
    positions, radii = rng.uniform(0.0, 100.0, (n, 2)), rng.uniform(0.05, 0.5, n)
    pairs, depths = touching_segments(positions, radii, segments, np.array(BOX))
    points = shapely.points(positions)
    lines = [shapely.linestrings(s.reshape(2, 2)) if s[0] != s[2] or s[1] != s[3] else shapely.points(s[:2])
             for s in segments]
    exact = np.stack([radii - shapely.distance(points, line) for line in lines], axis=1)   # (n, m), shapely's
    expected = {tuple(pair) for pair in np.argwhere(exact > 1e-12).tolist()}
    found = {tuple(pair): depth for pair, depth in zip(pairs.tolist(), depths)}
    assert [tuple(pair) for pair in pairs.tolist()] == sorted(found)   # bodies, then segments, in order
    assert expected <= set(found) and all(exact[pair] > -1e-12 for pair in found)
    assert all(abs(found[pair] - exact[pair]) < 1e-12 for pair in found)
    assert len(expected) > 10
