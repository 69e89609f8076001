"""The broad phase of the event-driven simulation: a uniform grid of cells.

The box is cut into nx × ny cells at least one particle diameter wide (plus a
safety margin), and every particle belongs to the cell holding its centre. Two
particles can then only touch if their cells are neighbours (3 × 3 block), so a
particle predicts collisions only with the particles of its block.

Crossing into another cell is itself an event (a 1D time to the cell's side),
processed like a collision without a velocity change: the particle moves to its
new cell and predicts again with its new neighbours. Nothing is ever missed, at
any speed: a fast particle simply has many crossing events.

Segments are registered once, in every cell they come within one maximum
radius of (found through the static index, statics/segment_index.py), so a
particle tests only the segments listed in its own cell.

Cell membership is a doubly linked list per cell (head, next, prev), so moving
a particle is O(1).

Mixed sizes. Sizing every cell by the largest diameter lets one large disk among
many small ones put hundreds of small ones in each cell. So a few large bodies
may be kept *apart* (choose_apart): the cells are sized by the others, the large
ones are filed in no cell list (they still have a cell, whose crossings are
their events), and a pair involving one is found from both sides: a body tests
every large body (few) whose cell is within reach of its own, and a large body
tests the bodies of the block of cells its radius reaches (reach_cells). Results
are the same events as with cells sized by the largest body.
"""
from collections import namedtuple

import numpy as np

from ..core.compiling import compiled, kernel
from ..core.geometry.segment import segment_meets_rect
from ..statics.segment_index import build_segment_index, segments_near

CellGrid = namedtuple("CellGrid", ["x0", "y0", "cell_w", "cell_h", "nx", "ny", "cell", "head", "next", "prev",
                                   "segment_start", "segment_index", "apart", "reach"])
CellGrid.__doc__ = """x0, y0: the box's lower left corner; cell_w, cell_h: cell size; nx, ny: cells per axis.
cell (n,): each particle's cell (cy * nx + cx); head (nx*ny,), next (n,), prev (n,): linked lists (-1 = none).
segment_start (nx*ny + 1,), segment_index (k,): the segments near cell c are
segment_index[segment_start[c]:segment_start[c + 1]] (the segments of bodies kept apart are all).
apart (L,): the large bodies kept out of the cell lists, in index order; reach (n,): how many
cells each side of its own a body's pairs may lie in (1 for the bodies in the lists, >= 2 for
those kept apart)."""

# At most this many bodies are kept apart: every other body tests each of them at its events.
MOST_APART = 64
# ... and only when that at least halves the bodies a typical event tests.
APART_GAIN = 2.0

# Cells are made this much wider than a diameter, so that a centre which is a few
# rounding errors outside its cell still only touches its 3 × 3 block.
CELL_MARGIN = 1e-6


# Bodies that settle (under gravity, sleeping on: engine/ccd/sleep.py) end up packed about a
# diameter apart, many times denser than spread over the box: their cells are a diameter wide,
# but no more than this many per body (a few bodies in a large box). In the settling
# particles_250 gas this cuts the bodies an event tests from 32 to about 14, and the settling's
# cost by a third.
PACKED_CELLS_PER_BODY = 8


def _cell_side(area, n, radius, packed=False):
    """Cells about one particle's share of the area (packed: a PACKED_CELLS_PER_BODY-th of it),
    never narrower than 2 radius (a number, or an array of radii: one side each)."""
    share = area / max(n, 1) / (PACKED_CELLS_PER_BODY if packed else 1)
    return np.maximum(2.0 * radius * (1.0 + CELL_MARGIN), np.sqrt(share))


def choose_apart(box, radii, packed=False) -> np.ndarray:
    """The largest bodies to keep apart (index order): the count L <= MOST_APART minimising
    the bodies an event tests, about 9 n side(L)² / area of the 3 × 3 block plus the L kept
    apart, where side(L) is the cell side the others need; none unless it gains APART_GAIN."""
    n = len(radii)
    if n < 2:
        return np.zeros(0, np.int64)
    area = (box[2] - box[0]) * (box[3] - box[1])
    largest_first = np.argsort(-radii, kind="stable")
    counts = np.arange(min(MOST_APART, n - 1) + 1)
    sides = _cell_side(area, n, radii[largest_first[counts]], packed)
    tested = 9.0 * n * sides ** 2 / area + counts
    best = int(np.argmin(tested))
    if best == 0 or tested[best] * APART_GAIN > tested[0]:
        return np.zeros(0, np.int64)
    return np.sort(largest_first[:best]).astype(np.int64)


def make_grid(box, radii, segments, separate_large=True, packed=False):
    """A grid for particles of these radii in box (xmin, ymin, xmax, ymax).

    Cells are about as large as one particle's share of the area (so about one
    particle per cell), but never narrower than the largest diameter of the bodies in
    the cell lists; with separate_large, a few large bodies may be kept apart (module
    docstring). packed: the bodies will settle into a pile (PACKED_CELLS_PER_BODY).
    """
    n = len(radii)
    width, height = box[2] - box[0], box[3] - box[1]
    apart = choose_apart(box, radii, packed) if separate_large else np.zeros(0, np.int64)
    listed_radii = np.delete(radii, apart)
    largest = listed_radii.max() if len(listed_radii) else 0.0
    side = _cell_side(width * height, n, largest, packed)
    nx, ny = max(1, int(width // side)), max(1, int(height // side))
    cell_w, cell_h = width / nx, height / ny
    reach = np.ones(n, np.int64)
    # a large body and another within one cell side of it: centres up to r + largest apart
    # (at least 2, which is how a body kept apart is told from the others)
    reach[apart] = np.maximum(np.ceil((radii[apart] + largest) * (1.0 + CELL_MARGIN) / min(cell_w, cell_h)), 2)
    grid = CellGrid(float(box[0]), float(box[1]), cell_w, cell_h, nx, ny,
                    np.full(n, -1, np.int64), np.full(nx * ny, -1, np.int64), np.full(n, -1, np.int64),
                    np.full(n, -1, np.int64), np.zeros(nx * ny + 1, np.int64), np.zeros(0, np.int64), apart, reach)
    if len(segments) == 0:   # every cell's list is empty (and the static index never compiles)
        return grid
    start, listed = _register_segments(grid, segments, build_segment_index(segments, box),
                                       largest * (1.0 + CELL_MARGIN))
    return grid._replace(segment_start=start, segment_index=listed)


@compiled(error_model="numpy")
def _register_segments(grid, segments, index, reach):
    """CSR lists (start, listed) of the segments within `reach` of each cell: the static
    index's candidates near the cell, kept if they really meet the cell grown by reach."""
    cells = grid.nx * grid.ny
    near = np.empty(max(segments.shape[0], 1), np.int64)
    start = np.zeros(cells + 1, np.int64)
    listed = np.empty(0, np.int64)
    for fill in range(2):  # count, then fill
        count = 0
        for c in range(cells):
            left, bottom, right, top = cell_bounds(grid, c)
            left, bottom, right, top = left - reach, bottom - reach, right + reach, top + reach
            for k in range(segments_near(index, left, bottom, right, top, near)):
                s = near[k]
                if segment_meets_rect(segments[s, 0], segments[s, 1], segments[s, 2], segments[s, 3],
                                      left, bottom, right, top):
                    if fill:
                        listed[count] = s
                    count += 1
            if not fill:
                start[c + 1] = count
        if not fill:
            listed = np.empty(count, np.int64)
    return start, listed


@kernel
def cell_bounds(grid, c):
    """(left, bottom, right, top) of cell c."""
    cx, cy = c % grid.nx, c // grid.nx
    left, bottom = grid.x0 + cx * grid.cell_w, grid.y0 + cy * grid.cell_h
    return left, bottom, left + grid.cell_w, bottom + grid.cell_h


@kernel
def cell_at(grid, x, y):
    """The cell holding point (x, y); points outside the box go to the nearest cell."""
    cx = min(max(int((x - grid.x0) // grid.cell_w), 0), grid.nx - 1)
    cy = min(max(int((y - grid.y0) // grid.cell_h), 0), grid.ny - 1)
    return cy * grid.nx + cx


@kernel
def is_apart(grid, i):
    """Is body i one of the large bodies kept out of the cell lists? (Their reach is > 1.)"""
    return grid.reach[i] > 1


@kernel
def segment_range(grid, i, m):
    """The segments body i may touch, of m: (first, last, every). Segment k for k in first ..
    last - 1 is k itself when `every` (a large body kept apart tests them all), else
    grid.segment_index[k] (those passing through its cell)."""
    if is_apart(grid, i):
        return 0, m, True
    c = grid.cell[i]
    return grid.segment_start[c], grid.segment_start[c + 1], False


@kernel
def move(grid, i, c):
    """Body i (in cell grid.cell[i] or none) now belongs to cell c."""
    if is_apart(grid, i):
        grid.cell[i] = c
        return
    if grid.cell[i] >= 0:
        unlink(grid, i)
    link(grid, i, c)


@kernel
def link(grid, i, c):
    """Put particle i (in no list) at the front of cell c's list."""
    first = grid.head[c]
    grid.next[i], grid.prev[i] = first, -1
    if first >= 0:
        grid.prev[first] = i
    grid.head[c] = i
    grid.cell[i] = c


@kernel
def unlink(grid, i):
    """Take particle i out of its cell's list."""
    before, after = grid.prev[i], grid.next[i]
    if before >= 0:
        grid.next[before] = after
    else:
        grid.head[grid.cell[i]] = after
    if after >= 0:
        grid.prev[after] = before
    grid.cell[i] = -1


@kernel
def assign_all(grid, positions):
    """Rebuild every cell list from positions (n, 2), particles in index order."""
    grid.head[:] = -1
    for i in range(positions.shape[0] - 1, -1, -1):
        grid.cell[i] = -1
        move(grid, i, cell_at(grid, positions[i, 0], positions[i, 1]))


@kernel
def neighbour_block(grid, c):
    """The 3 × 3 block of cells around cell c (smaller at the box edges), as column and
    row ranges (cx_lo, cx_hi, cy_lo, cy_hi): its cells are cy * nx + cx for cy in
    range(cy_lo, cy_hi), cx in range(cx_lo, cx_hi). (Plain numbers rather than an
    array of cells: this is asked for at every event, and an array would be allocated.)"""
    return reach_block(grid, c, 1)


@kernel
def reach_block(grid, c, reach):
    """The (2 reach + 1)² block of cells around cell c, as neighbour_block."""
    cx, cy = c % grid.nx, c // grid.nx
    return max(cx - reach, 0), min(cx + reach + 1, grid.nx), max(cy - reach, 0), min(cy + reach + 1, grid.ny)

