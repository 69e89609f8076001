"""Uniform grid: chop space into equal square cells.

Lay a grid of square cells over the scene and put every box into each cell
it overlaps. Two boxes can only overlap if they share a cell, so only boxes
in the same cell are tested against each other — with cells about the size
of a particle, each cell holds a handful of boxes and the work is close to
linear in n.

Filling the cells — a counting sort instead of a dictionary of lists:

1. count how many boxes land in each cell;
2. running totals (prefix sums) of the counts say where each cell's run of
   boxes ends in one flat array (``cell_boxes``);
3. walk the boxes again, last to first, and drop each into the last free
   slot of each of its cells' runs. When done, every run is filled, its
   boxes are in increasing index order, and the running totals have stepped
   back to where each run starts (``cell_start``).

Two overlapping boxes may share several cells. To report each pair exactly
once we report it only from the cell holding the lower-left corner of the
two boxes' intersection: that point lies in both boxes, so both boxes were
put in its cell, and a point lies in exactly one cell.

Cell size. By default twice the median box extent: a typical box then
touches 1 to 4 cells, and the few large boxes are simply inserted into more
cells (a circle 100 times bigger than the rest costs more insertions, not a
grid of giant cells for everybody). The size is widened when needed so a
sparse scene never has more than about 4n cells. Pass ``cell_size=`` to
choose it yourself.

A box query looks only at the cells the query box covers; a ray cast walks
the cells along the ray in order (Amanatides & Woo) and tests only the boxes
filed in them (see :mod:`.grid_walk`).
"""

import numpy as np

from ..core.compiling import compiled, kernel
from ._common import (BroadPhase, bounding_box, box_meets_query, boxes_overlap, check_boxes,
                      check_positive_option, new_pair_buffer, push_index, push_pair)
from .grid_walk import grid_raycast

MAX_CELLS = 1 << 24  # 16.8 million cells: 134 MB of cell_start alone
# The narrowest cell: the smallest normal float (2.2e-308). Below about 5.6e-309, 1 / cell_size
# overflows to inf, and (x - origin) * inf is inf or nan, no cell at all. The pairs are right at
# any cell size; narrower cells would only spread boxes a few subnormals wide over more cells.
NARROWEST_CELL = float(np.finfo(np.float64).tiny)


def default_cell_size(lo: np.ndarray, hi: np.ndarray) -> float:
    """Twice the median box extent, widened so the grid has about 4n cells at most, and to
    NARROWEST_CELL (boxes a few subnormal floats wide); 1.0 when every box is one point."""
    extents = np.maximum(hi[:, 0] - lo[:, 0], hi[:, 1] - lo[:, 1])
    corner_lo, corner_hi = bounding_box(lo, hi)
    span = np.max(corner_hi - corner_lo)
    size = max(2.0 * float(np.median(extents)), float(span) / np.sqrt(4 * len(lo)))
    return max(size, NARROWEST_CELL) if size > 0 else 1.0


def grid_layout(lo: np.ndarray, hi: np.ndarray, cell_size: float) -> tuple[np.ndarray, tuple[int, int]]:
    """Origin (2,) and shape (nx, ny) of a grid of `cell_size` cells covering all boxes."""
    origin, corner_hi = bounding_box(lo, hi)
    # The same arithmetic as cell_of, so the last box lands in the last cell. Counted in floats
    # and checked before they become integers: a count past 2^63 (or its square) wraps around
    # int64, to a grid of no cells that pairs nothing.
    with np.errstate(over="ignore"):
        nx, ny = np.floor((corner_hi - origin) * (1.0 / cell_size)) + 1
    if not float(nx) * float(ny) <= MAX_CELLS:
        raise ValueError(f"cell_size={cell_size:g} gives a {nx:g} x {ny:g} grid "
                         f"(more than {MAX_CELLS} cells); use a larger cell_size")
    return origin, (int(nx), int(ny))


@kernel
def cell_of(x, origin, cells_per_unit, n_cells):
    """Grid column (or row) holding coordinate x, clamped to 0 .. n_cells - 1.

    cells_per_unit is 1 / cell_size: multiplying is cheaper than dividing.
    """
    k = int(np.floor((x - origin) * cells_per_unit))
    return min(max(k, 0), n_cells - 1)


@kernel
def cell_range(lo, hi, i, origin, cells_per_unit, nx, ny):
    """First and last column and row of the cells box i overlaps."""
    return (cell_of(lo[i, 0], origin[0], cells_per_unit, nx),
            cell_of(hi[i, 0], origin[0], cells_per_unit, nx),
            cell_of(lo[i, 1], origin[1], cells_per_unit, ny),
            cell_of(hi[i, 1], origin[1], cells_per_unit, ny))


@compiled
def bin_boxes(lo, hi, origin, cells_per_unit, nx, ny):
    """Counting-sort the boxes into the cells they overlap.

    lo, hi: (n, 2); origin: (2,); cells_per_unit = 1 / cell_size.
    Cell (ix, iy) has id ix * ny + iy. Returns cell_start (nx * ny + 1,) and
    cell_boxes (total insertions,): the boxes of cell c are
    cell_boxes[cell_start[c]:cell_start[c + 1]], in increasing index order.
    """
    n = lo.shape[0]
    cell_start = np.zeros(nx * ny + 1, np.intp)
    # 1. Count the boxes in each cell.
    for i in range(n):
        x0, x1, y0, y1 = cell_range(lo, hi, i, origin, cells_per_unit, nx, ny)
        for ix in range(x0, x1 + 1):
            for iy in range(y0, y1 + 1):
                cell_start[ix * ny + iy] += 1
    # 2. Running totals: cell_start[c] is now where cell c's run *ends*.
    for cell in range(1, nx * ny + 1):
        cell_start[cell] += cell_start[cell - 1]
    # 3. Fill each run from its end, taking the boxes last to first; every
    #    cell_start[c] steps back to the start of its run, and each run ends
    #    up in increasing index order.
    cell_boxes = np.empty(cell_start[nx * ny], np.intp)
    for i in range(n - 1, -1, -1):
        x0, x1, y0, y1 = cell_range(lo, hi, i, origin, cells_per_unit, nx, ny)
        for ix in range(x0, x1 + 1):
            for iy in range(y0, y1 + 1):
                cell = ix * ny + iy
                cell_start[cell] -= 1
                cell_boxes[cell_start[cell]] = i
    return cell_start, cell_boxes


@compiled
def grid_pairs(lo, hi, origin, cells_per_unit, nx, ny, cell_start, cell_boxes):
    """Overlapping pairs among boxes sharing a cell, each reported once.

    lo, hi: (n, 2); the other arguments as for and from bin_boxes.
    Returns (k, 2) intp pairs with i < j.
    """
    pairs, count = new_pair_buffer(lo.shape[0]), np.intp(0)
    for cell in range(nx * ny):
        first, end = cell_start[cell], cell_start[cell + 1]
        if end - first < 2:
            continue  # most cells: nothing to pair, skip them early
        ix, iy = cell // ny, cell % ny
        for a in range(first, end):
            i = cell_boxes[a]
            for b in range(a + 1, end):
                j = cell_boxes[b]
                if not boxes_overlap(lo, hi, i, j):
                    continue
                # Report from the cell of the intersection's lower-left corner only.
                corner_x = max(lo[i, 0], lo[j, 0])
                corner_y = max(lo[i, 1], lo[j, 1])
                if (cell_of(corner_x, origin[0], cells_per_unit, nx) == ix
                        and cell_of(corner_y, origin[1], cells_per_unit, ny) == iy):
                    pairs, count = push_pair(pairs, count, i, j)
    return pairs[:count]


@compiled
def cell_bounds(origin, cell_size, cells_per_unit, n_cells, upper):
    """The extent of each column (or row) of the grid, as cell_of sees it.

    Returns starts, ends (n_cells,): every coordinate x that cell_of puts in
    cell k has starts[k] <= x <= ends[k]; both ascend. The first cell starts
    at the origin and the last ends at `upper`, the far side of the boxes'
    bounding box (nothing lies beyond it).

    The edge between cells k - 1 and k is about origin + k * cell_size, but
    cell_of rounds (x - origin) * cells_per_unit, so points a few units in the
    last place from it may land on either side. Each inner edge therefore
    gets a margin, doubled until cell_of confirms it: neighbouring cells
    overlap by that sliver, and a ray walk that uses these bounds never
    misses the cell bin_boxes filed a box in.
    """
    starts = np.empty(n_cells)
    ends = np.empty(n_cells)
    starts[0] = origin
    ends[n_cells - 1] = upper
    for k in range(1, n_cells):
        x = origin + k * cell_size
        margin = (abs(x) + cell_size) * 2.0 ** -52  # about one unit in the last place
        while not (cell_of(x - margin, origin, cells_per_unit, n_cells) < k
                   and cell_of(x + margin, origin, cells_per_unit, n_cells) >= k):
            margin *= 2.0
        starts[k] = max(x - margin, starts[k - 1])  # stays ascending: only ever raised
        ends[k - 1] = x + margin
    for k in range(1, n_cells):
        ends[k] = max(ends[k], ends[k - 1])
    return starts, ends


@compiled
def grid_query(lo, hi, origin, cells_per_unit, nx, ny, cell_start, cell_boxes,
               qx0, qy0, qx1, qy1):
    """Boxes overlapping the query box [qx0, qx1] x [qy0, qy1], each once.

    lo, hi: (n, 2); the other arguments as for and from bin_boxes. Returns
    (found (k,) intp, cells visited, boxes tested). A box overlapping the
    query shares at least one cell with it; like grid_pairs, each box is
    reported only from the cell holding the lower-left corner of its overlap
    with the query box.
    """
    found, count = np.empty(16, np.intp), np.intp(0)
    x0 = cell_of(qx0, origin[0], cells_per_unit, nx)
    x1 = cell_of(qx1, origin[0], cells_per_unit, nx)
    y0 = cell_of(qy0, origin[1], cells_per_unit, ny)
    y1 = cell_of(qy1, origin[1], cells_per_unit, ny)
    tested = 0
    for ix in range(x0, x1 + 1):
        for iy in range(y0, y1 + 1):
            cell = ix * ny + iy
            for a in range(cell_start[cell], cell_start[cell + 1]):
                i = cell_boxes[a]
                tested += 1
                if (box_meets_query(lo, hi, i, qx0, qy0, qx1, qy1)
                        and cell_of(max(lo[i, 0], qx0), origin[0], cells_per_unit, nx) == ix
                        and cell_of(max(lo[i, 1], qy0), origin[1], cells_per_unit, ny) == iy):
                    found, count = push_index(found, count, i)
    return found[:count], (x1 - x0 + 1) * (y1 - y0 + 1), tested


class UniformGrid(BroadPhase):
    """Uniform grid broad phase; ``stats["memory_bytes"]`` is the grid arrays' size."""

    name = "grid"
    OPTIONS = ("cell_size",)
    EMPTY_STATS = {"memory_bytes": 0}

    def __init__(self, cell_size=None):
        super().__init__()
        self.cell_size = None if cell_size is None else check_positive_option("cell_size", cell_size)
        if self.cell_size is not None and self.cell_size < NARROWEST_CELL:
            raise ValueError(f"cell_size must be at least {NARROWEST_CELL:g}; got {cell_size!r}")

    def _bin(self, lo: np.ndarray, hi: np.ndarray):
        cell_size = default_cell_size(lo, hi) if self.cell_size is None else self.cell_size
        origin, (nx, ny) = grid_layout(lo, hi, cell_size)
        cell_start, cell_boxes = bin_boxes(lo, hi, origin, 1.0 / cell_size, nx, ny)
        return origin, cell_size, (nx, ny), cell_start, cell_boxes

    def _find(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        origin, cell_size, (nx, ny), cell_start, cell_boxes = self._bin(lo, hi)
        self.stats.update(cell_size=cell_size, shape=(nx, ny),
                          memory_bytes=cell_start.nbytes + cell_boxes.nbytes)
        return grid_pairs(lo, hi, origin, 1.0 / cell_size, nx, ny, cell_start, cell_boxes)

    def _query(self, lo, hi, qx0, qy0, qx1, qy1):
        (x0, y0), (x1, y1) = bounding_box(lo, hi)
        if qx1 < x0 or qx0 > x1 or qy1 < y0 or qy0 > y1:
            # Outside the grid: cell_of would clamp it onto the border cells.
            return np.empty(0, np.intp), 0, 0
        origin, cell_size, (nx, ny), cell_start, cell_boxes = self._bin(lo, hi)
        return grid_query(lo, hi, origin, 1.0 / cell_size, nx, ny, cell_start, cell_boxes,
                          qx0, qy0, qx1, qy1)

    def _raycast(self, lo, hi, ox, oy, ux, uy, max_distance):
        origin, cell_size, (nx, ny), cell_start, cell_boxes = self._bin(lo, hi)
        _, corner_hi = bounding_box(lo, hi)
        cells_per_unit = 1.0 / cell_size
        columns = cell_bounds(origin[0], cell_size, cells_per_unit, nx, corner_hi[0])
        rows = cell_bounds(origin[1], cell_size, cells_per_unit, ny, corner_hi[1])
        return grid_raycast(lo, hi, cell_start, cell_boxes, *columns, *rows,
                            ox, oy, ux, uy, max_distance)

    def describe(self, lo, hi) -> dict:
        """Grid origin, cell size, shape (nx, ny), boxes per cell (nx, ny), and
        the pairs, for n >= 1 boxes."""
        lo, hi = check_boxes(lo, hi)
        if len(lo) == 0:
            raise ValueError("describe() needs at least one box")
        origin, cell_size, shape, cell_start, _ = self._bin(lo, hi)
        return {
            "origin": origin,
            "cell_size": cell_size,
            "shape": shape,
            "counts": np.diff(cell_start).reshape(shape),
            "pairs": self.pairs(lo, hi),
        }
