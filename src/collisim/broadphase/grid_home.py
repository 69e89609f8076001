"""The uniform grid as the discrete step runs it, every step: each box filed once, in its home
cell, and the boxes gathered into cell order.

grid.py files a box in every cell it overlaps and pairs the boxes sharing a cell. That works
for boxes of any size, but it allocates and scans the whole grid each call, and reads the boxes
in the caller's order, which at 10^5 bodies is mostly cache misses. The step calls the broad
phase on boxes of much the same size, every step, so here:

* cells as wide as the widest box (home_cells_per_unit), and each box filed only in
  its *home* cell, the cell of its lower-left corner. Two overlapping boxes then have home
  cells at most one apart on each axis (box i starts no farther right than box j ends, and box
  j is narrower than a cell), so a cell need only meet itself and its forward half of the 3 x 3
  neighbourhood: north, and the east column (south-east, east, north-east). Each pair of
  neighbouring cells meets once, so each overlapping pair is found once.
* a counting sort on the home cells moves the boxes (and their indices) into cell order, so
  the pair tests read a cell's and its neighbours' boxes from contiguous memory. With the cells
  numbered column by column (as grid.py does), the forward neighbours are two contiguous runs:
  the cell itself followed by its north neighbour, and the three cells of the east column (with
  an empty cell padding each column's ends and an empty column after the last, no edge needs a
  test).
* a box meets the east column only if its right edge lies in a later column than its home (every
  box filed there starts in that column), and the north row (north, north-east) only if its top
  edge lies in a later row: most boxes, much narrower than a cell, reach neither, and their scan
  skips those cells instead of testing every box in them (each test a miss). The filing works
  out both with the home cell (home_and_reach), so the scan reads no more than it did.
* the arrays are kept between steps (GridState): the counts are zero between calls because the
  pair scan, which visits exactly the occupied cells, resets each one it visits. One pass over
  all cells remains, the running totals; nothing is allocated but the pairs.

The pairs are the boxes' original indices (i < j), in cell order: the step sorts them.
"""

import numpy as np

from ..core.arrays import grown
from ..core.compiling import compiled, kernel
from ._common import boxes_overlap
from .grid import cell_of

FITS = 1.0 - 2.0 ** -20   # widest box / cell width at most this: the home-cell rule then holds
                          # with room for the rounding of (x - origin) * cells_per_unit (an error
                          # of a few units in the last place of the column number, ~1e-9 at 10^7
                          # columns)
WIDEST_CELL = 2.0         # cells wider than this many of the grid's own: file boxes in grid.py's way
MOST_CELLS = 2 ** 29      # home cells numbered below this: a cell times 4 plus a box's reach fits in int32
EAST, NORTH = 1, 2        # home_and_reach's bits


@compiled(fastmath={"nnan", "nsz", "reassoc"})
def home_cells_per_unit(lo, hi, finest, cells_per_unit):
    """1 / the cell width for home-cell filing: cells as wide as the widest box (over FITS), the
    fewer boxes a box is tested against the better, but no narrower than 1 / finest (the
    scratch's grid); 0.0 when they would be more than WIDEST_CELL times the grid's own cells
    (1 / cells_per_unit) wide. fastmath (no NaN, reassociation) lets the maximum be taken several
    lanes at a time: it is exact in any order, and boxes are finite."""
    widest = 0.0
    for i in range(lo.shape[0]):
        for axis in range(2):
            # (comparisons, not max() and min(): under fastmath those would compile anew)
            widest = hi[i, axis] - lo[i, axis] if hi[i, axis] - lo[i, axis] > widest else widest
    per_unit = FITS / widest if widest * finest > FITS else finest
    return per_unit if per_unit * WIDEST_CELL >= cells_per_unit else 0.0


def home_layout(width: float, height: float, cell: float, most_radius: float, n: int) -> tuple:
    """The finest grid home-cell filing may use over a width x height box for n boxes: cells no
    narrower than the widest box can be (a box is at least its circle's diameter, 2 * most_radius)
    nor than leaves about 4n cells, nor wider than `cell`. Returns (1 / its cell width, nx, ny)."""
    fine = min(cell, max(2.0 * most_radius, np.sqrt(width * height / (4 * max(n, 1)))))
    return 1.0 / fine, int(width // fine) + 1, int(height // fine) + 1


def home_scratch(nx: int, ny: int, n: int) -> tuple:
    """home_grid_pairs' scratch for n boxes in an nx x ny grid (or one of fewer, wider cells):
    count, start for its (nx + 1) * (ny + 2) cells, zero and empty; ids, cell_lo, cell_hi; room;
    homes and cell_homes (n,), each box's home_and_reach by index and in cell order. int32 counts
    and cells: half the memory traffic (about 4n cells, so n up to some 10^8; a grid of more than
    MOST_CELLS cells gets room for no box)."""
    cells = (nx + 1) * (ny + 2)
    boxes = n if cells < MOST_CELLS else 0   # (no room for boxes: the step files them in grid.py's way)
    return (np.zeros(cells, np.int32), np.empty(cells + 1, np.int32), np.empty(boxes, np.intp), np.empty((boxes, 2)),
            np.empty((boxes, 2)), np.full(1, boxes // 8, np.intp), np.empty(boxes, np.int32),
            np.empty(boxes, np.int32))


@kernel
def home_and_reach(lo, hi, i, origin, per_unit, nx, ny):
    """Box i's home cell, the cell of its lower-left corner, in the padded numbering of
    home_grid_pairs (ix * (ny + 2) + iy + 1), times 4, plus the forward neighbours it can
    reach: EAST if its right edge is not left of the next column, NORTH if its top edge is not
    below the next row. A box filed in the next column starts at least there, so (the cell of a
    coordinate never decreasing as it grows) one that does not reach it lies wholly to the right
    of box i; the same for rows. A NaN edge reaches both."""
    ix = cell_of(lo[i, 0], origin[0], per_unit, nx)
    iy = cell_of(lo[i, 1], origin[1], per_unit, ny)
    east = not (hi[i, 0] - origin[0]) * per_unit < ix + 1
    north = not (hi[i, 1] - origin[1]) * per_unit < iy + 1
    return (ix * (ny + 2) + iy + 1) * 4 + EAST * east + NORTH * north


@compiled
def home_grid_pairs(lo, hi, origin, per_unit, nx, ny, count, start, ids, cell_lo, cell_hi, room, homes, cell_homes):
    """Every pair of overlapping boxes lo, hi (n, 2) once, as original indices (k, 2), i < j,
    in cell order, for cells of 1 / per_unit (home_cells_per_unit) in an nx x ny grid.

    The cells are numbered column by column with an empty cell below and above each column and
    an empty column after the last, ix * (ny + 2) + iy + 1, so that every cell has the forward
    neighbours the scan reads, without a test at the grid's edges.

    Scratch kept between calls (home_scratch): count, zero on entry and on return, and start;
    ids and cell_lo, cell_hi for the boxes in cell order; room (1,): the pair buffer's size to
    start from (the last call's pair count, plus some); homes and cell_homes, each box's home
    cell by index and in cell order (worked out once a call: working it out again in the
    filling and in the scan was a quarter of the grid's time at a thousand boxes).
    """
    n = lo.shape[0]
    column = ny + 2
    cells = (nx + 1) * column                       # as home_scratch counts them
    # 1. How many boxes each cell is home to (and what each box reaches).
    for i in range(n):
        homes[i] = home_and_reach(lo, hi, i, origin, per_unit, nx, ny)
        count[homes[i] >> 2] += 1
    # 2. Running totals: start[c] is where cell c's run ends (the one pass over every cell).
    total = 0
    for c in range(cells):
        total += count[c]
        start[c] = total
    start[cells] = total
    # 3. Fill each run from its end, boxes last to first, copying the boxes along: every
    #    start[c] steps back to its run's start and each run is in increasing index order.
    for i in range(n - 1, -1, -1):
        c = homes[i] >> 2
        k = start[c] - 1
        start[c] = k
        ids[k], cell_homes[k] = i, homes[i]
        cell_lo[k, 0], cell_lo[k, 1], cell_hi[k, 0], cell_hi[k, 1] = lo[i, 0], lo[i, 1], hi[i, 0], hi[i, 1]
    # 4. The pairs, into a buffer grown between scans when a box's tests might overflow it.
    pairs, found, a = np.empty((max(16, room[0]), 2), np.intp), np.intp(0), np.intp(0)
    while a < n:
        a, found = scan_cells(cell_lo, cell_hi, ids, cell_homes, start, count, a, n, column, pairs, found)
        if a < n:
            pairs = grown(pairs, found + pairs.shape[0] + n)   # room for any box's tests
    room[0] = found + found // 4 + 16
    return pairs[:found]


@kernel
def scan_cells(cell_lo, cell_hi, ids, cell_homes, start, count, a, n, column, pairs, found):
    """The overlapping pairs of boxes a, a + 1, ... < n (in cell order: home_grid_pairs) into pairs
    from row `found` on, until a box's tests might not fit. Returns (the next box, found).

    Box by box rather than cell by cell: each box finds its two runs (the rest of its cell, and
    its north neighbour if it reaches it; the east column's south-east and east cells, and the
    north-east one, if it reaches that column: home_and_reach) from its own cell, so the boxes'
    lookups overlap in the processor instead of each cell waiting for the last one's end. Every
    test writes its pair and only a hit advances `found` (no branch to mispredict: most tests
    miss); the buffer is not grown in here, which would make numba count references to it on
    every box."""
    while a < n:
        c, north = cell_homes[a] >> 2, (cell_homes[a] & NORTH) >> 1
        own = start[c + 1 + north] - a - 1
        east_first = start[c + column - 1]
        east = start[c + column + 1 + north] - east_first if cell_homes[a] & EAST else 0
        if found + own + east > pairs.shape[0]:
            return a, found
        count[c] = 0                                    # zero again for the next call
        i = ids[a]
        for t in range(own + east):                     # the two runs as one loop
            b = a + 1 + t if t < own else east_first + t - own
            j = ids[b]
            pairs[found, 0], pairs[found, 1] = min(i, j), max(i, j)
            found += boxes_overlap(cell_lo, cell_hi, a, b)
        a += 1
    return a, found
