"""A static index of thin segments: which segments are near a body?

Level geometry (thin segments, rows (x0, y0, x1, y1)) never moves, so it is
indexed once and queried every step. Testing every body against every segment
is O(n·m); with the index a body tests only the segments registered in the
cells its bounding box overlaps, which is O(1) for short segments.

The index is a uniform grid of square cells over the box and the segments'
bounding box, stored in CSR form (a counting sort, as in
``collisim.broadphase.grid``): cell c = cy * nx + cx holds the segments
``cell_segments[cell_start[c]:cell_start[c + 1]]``, in ascending order.

A segment is registered in exactly the cells its line passes through, not in
its whole bounding box: a long diagonal across a 1000 × 1000-cell grid is put
in about 2000 cells, not a million. Each candidate cell is confirmed with an
exact segment–rectangle test (Liang–Barsky clipping, closed rectangles), so a
segment lying on a cell edge registers in both neighbours and a zero-length
segment behaves as a point. The candidates are found column by column: the
part of the segment inside a column of cells spans a small range of rows, so
registering costs O(length / cell), even with a fine user-chosen cell.

Rounding. Cell edges computed as ``x0 + k * cell`` and the cell index
``floor((x - x0) / cell)`` can disagree by an ulp or so at an edge, and
clipping a segment that only grazes a corner can round to "empty". So each
cell is tested grown by a tolerance far above rounding (1e-9 of a cell, plus a
few ulps of the coordinates) and far below anything visible: a segment within
that distance of a cell is registered in it. This is what makes the query
guarantee below hold in floating point, at the price of a rare extra segment.

Query guarantee (``segments_near``): every segment that meets the closed query
box [lo_x, hi_x] × [lo_y, hi_y] is reported. To find the segments within
distance r of a point, query the box grown by r on every side. Segments that
do not meet the box may be reported too (they share a cell with it); the
caller's exact test sorts them out.

Queries use per-index scratch (``mark``, ``stamp``): an index is not safe to
query from several threads at once; give each thread its own copy of those two
arrays (``index._replace(mark=..., stamp=...)``).
"""
from collections import namedtuple

import numpy as np

from ..core.arrays import heap_sort
from ..core.compiling import compiled, kernel
from ..core.geometry.segment import clip_step

MAX_CELLS = 4_000_000  # 32 MB of cell_start; more cells than this buys nothing

SegmentIndex = namedtuple("SegmentIndex", ["x0", "y0", "cell", "nx", "ny", "cell_start", "cell_segments",
                                           "mark", "stamp"])
SegmentIndex.__doc__ = """A grid index of m static segments, built by build_segment_index.

x0, y0 (float): the grid's lower left corner; cell (float): the side of a square cell;
nx, ny (int): cells per axis. Cell (cx, cy) is [x0 + cx*cell, x0 + (cx+1)*cell] × (same in y),
its id is c = cy * nx + cx.
cell_start (nx*ny + 1,) int64, cell_segments (total,) int64: the segments registered in cell c
are cell_segments[cell_start[c]:cell_start[c + 1]], ascending.
mark (m,) int64, stamp (1,) int64: query scratch. A query increments stamp[0] and sets
mark[s] = stamp[0] for each segment s it reports, so a segment found in several cells is
reported once, without clearing anything between queries."""


# ---------------------------------------------------------------- compiled kernels

@kernel
def cell_of(x, origin, inv_cell, n):
    """Column (or row) holding coordinate x, clamped to 0 .. n - 1.

    inv_cell is 1 / cell. The clamping is done on the float, before converting
    to an integer, so infinities and NaN (sent to 0) are safe too.
    """
    k = np.floor((x - origin) * inv_cell)
    if not k >= 0.0:
        return 0
    if k >= n - 1:
        return n - 1
    return int(k)


@kernel
def _walk_segment(segments, s, x0, y0, cell, nx, ny, tol, cell_start, cell_segments, fill):
    """Visit the cells segment s meets (each once). Counting pass (fill False):
    cell_start[c] += 1. Fill pass: cell_start[c] -= 1 and store s at the new cell_start[c]."""
    sx, sy = segments[s, 0], segments[s, 1]
    dx, dy = segments[s, 2] - sx, segments[s, 3] - sy
    inv = 1.0 / cell
    # The cells of the bounding box, one more on each side: a segment on (or within
    # tol of) a cell edge also meets the neighbour beyond that edge.
    col_lo = max(cell_of(min(sx, sx + dx), x0, inv, nx) - 1, 0)
    col_hi = min(cell_of(max(sx, sx + dx), x0, inv, nx) + 1, nx - 1)
    row_lo = max(cell_of(min(sy, sy + dy), y0, inv, ny) - 1, 0)
    row_hi = min(cell_of(max(sy, sy + dy), y0, inv, ny) + 1, ny - 1)
    for cx in range(col_lo, col_hi + 1):
        left, right = x0 + cx * cell - tol, x0 + (cx + 1) * cell + tol
        # The part of the segment inside this column: parameters [ta, tb]
        # (the first two Liang–Barsky steps, shared by every cell of the column).
        ta, tb = clip_step(-dx, sx - left, 0.0, 1.0)
        ta, tb = clip_step(dx, right - sx, ta, tb)
        if ta > tb:
            continue
        # That part only spans the rows between its two ends (±1 for rounding);
        # the exact test below decides, these bounds only save work.
        ya, yb = sy + ta * dy, sy + tb * dy
        first = max(cell_of(min(ya, yb), y0, inv, ny) - 1, row_lo)
        last = min(cell_of(max(ya, yb), y0, inv, ny) + 1, row_hi)
        for cy in range(first, last + 1):
            bottom, top = y0 + cy * cell - tol, y0 + (cy + 1) * cell + tol
            t0, t1 = clip_step(-dy, sy - bottom, ta, tb)
            t0, t1 = clip_step(dy, top - sy, t0, t1)
            if t0 > t1:
                continue
            c = cy * nx + cx
            if fill:
                cell_start[c] -= 1
                cell_segments[cell_start[c]] = s
            else:
                cell_start[c] += 1


@compiled
def _build_csr(segments, x0, y0, cell, nx, ny, tol):
    """Counting sort of the segments into the cells they meet.

    segments (m, 4). Returns cell_start (nx*ny + 1,) int64 and cell_segments (total,) int64.
    """
    m, cells = segments.shape[0], nx * ny
    cell_start = np.zeros(cells + 1, np.int64)
    empty = np.empty(0, np.int64)
    # 1. Count the segments of each cell.
    for s in range(m):
        _walk_segment(segments, s, x0, y0, cell, nx, ny, tol, cell_start, empty, False)
    # 2. Running totals: cell_start[c] is now where cell c's run *ends*.
    for c in range(1, cells + 1):
        cell_start[c] += cell_start[c - 1]
    # 3. Fill each run from its end, segments last to first: every cell_start[c]
    #    steps back to the start of its run, and each run ends up ascending.
    cell_segments = np.empty(cell_start[cells], np.int64)
    for s in range(m - 1, -1, -1):
        _walk_segment(segments, s, x0, y0, cell, nx, ny, tol, cell_start, cell_segments, True)
    return cell_start, cell_segments


@kernel
def segments_near(index, lo_x, lo_y, hi_x, hi_y, out):
    """The segments registered in the cells the box [lo_x, hi_x] × [lo_y, hi_y] overlaps.

    index: a SegmentIndex; out: (>= m,) int64, receives the distinct segment ids,
    ascending. Returns their count. Boxes partly or wholly outside the grid are
    clamped to its border cells. Guarantee: every segment that meets the box
    (closed, touching counts) is reported; segments merely near it may be too.
    Uses index.mark / index.stamp as scratch (one query at a time per index).
    """
    inv = 1.0 / index.cell
    col_lo = cell_of(lo_x, index.x0, inv, index.nx)
    col_hi = cell_of(hi_x, index.x0, inv, index.nx)
    row_lo = cell_of(lo_y, index.y0, inv, index.ny)
    row_hi = cell_of(hi_y, index.y0, inv, index.ny)
    # A fresh stamp: segments marked by earlier queries count as unseen, so
    # mark never needs clearing.
    index.stamp[0] += 1
    stamp = index.stamp[0]
    mark, cell_start, cell_segments = index.mark, index.cell_start, index.cell_segments
    count = 0
    for cy in range(row_lo, row_hi + 1):
        for cx in range(col_lo, col_hi + 1):
            c = cy * index.nx + cx
            for k in range(cell_start[c], cell_start[c + 1]):
                s = cell_segments[k]
                if mark[s] != stamp:
                    mark[s] = stamp
                    out[count] = s
                    count += 1
    # Ascending order, so callers treat segments in index order (deterministic
    # results, as with the all-segments loop). Lists are short: insertion sort;
    # a huge query box falls back to a heapsort rather than going quadratic.
    if count > 64:
        heap_sort(out, 0, count)
        return count
    for i in range(1, count):
        s = out[i]
        j = i - 1
        while j >= 0 and out[j] > s:
            out[j + 1] = out[j]
            j -= 1
        out[j + 1] = s
    return count


# ---------------------------------------------------------------- building (Python)

def _grid_shape(width, height, cell):
    """(nx, ny) of a grid of `cell` cells covering width × height, with the
    same arithmetic as cell_of, so the far corner lands in the last cell."""
    inv = 1.0 / cell
    return int(np.floor(width * inv)) + 1, int(np.floor(height * inv)) + 1


def _default_cell(segments, width, height):
    """About the mean segment length (a typical segment then meets 2 to 4 cells),
    widened until the grid has at most 4 m + 64 cells (and MAX_CELLS)."""
    m = len(segments)
    limit = min(4 * m + 64, MAX_CELLS)
    mean_length = float(np.mean(np.hypot(segments[:, 2] - segments[:, 0], segments[:, 3] - segments[:, 1])))
    cell = max(mean_length, np.sqrt(width * height / limit), max(width, height) / limit)
    if not cell > 0.0:  # all segments zero-length at one point, in a zero-area box
        return 1.0
    while np.prod(_grid_shape(width, height, cell)) > limit:  # a few steps at most
        cell *= 1.0625
    return float(cell)


def build_segment_index(segments, box, cell=None) -> SegmentIndex:
    """Index m static segments for "which segments are near this box?" queries.

    segments: (m, 4) float rows (x0, y0, x1, y1) (an (m, 2, 2) array is accepted too);
    box: (xmin, ymin, xmax, ymax). The grid covers the box and every segment, even
    those sticking out of the box. cell: the side of a square cell; by default about
    the mean segment length, coarsened so the grid has at most ~4 m + 64 cells.
    m = 0 gives an empty index with a single cell covering the box.
    """
    segments = np.ascontiguousarray(segments, dtype=np.float64).reshape(-1, 4)
    box = np.asarray(box, dtype=np.float64).reshape(4)
    if not (np.all(np.isfinite(segments)) and np.all(np.isfinite(box))):
        raise ValueError("segments and box must be finite")
    if box[0] > box[2] or box[1] > box[3]:
        raise ValueError(f"box must be (xmin, ymin, xmax, ymax), got {tuple(box)}")
    m = len(segments)
    lo, hi = box[:2].copy(), box[2:].copy()
    if m:
        lo = np.minimum(lo, np.minimum(segments[:, :2].min(axis=0), segments[:, 2:].min(axis=0)))
        hi = np.maximum(hi, np.maximum(segments[:, :2].max(axis=0), segments[:, 2:].max(axis=0)))
    width, height = float(hi[0] - lo[0]), float(hi[1] - lo[1])
    if cell is not None:
        cell = float(cell)
        if not (np.isfinite(cell) and cell > 0.0):
            raise ValueError(f"cell must be a positive number, got {cell}")
    if m == 0:
        # Nothing to find: one cell covering the box (queries clamp to it), whatever cell was asked.
        nx = ny = 1
        cell = max(width, height) or 1.0
    else:
        cell = cell if cell is not None else _default_cell(segments, width, height)
        nx, ny = _grid_shape(width, height, cell)
        if nx * ny > MAX_CELLS:
            raise ValueError(f"cell={cell:g} gives a {nx} x {ny} grid (more than {MAX_CELLS} cells); "
                             f"use a larger cell")
    # Far above rounding (relative 1e-9 of a cell, absolute a few ulps of the
    # coordinates), far below anything visible; see the module docstring.
    scale = float(np.max(np.abs(np.concatenate((lo, hi)))))
    tol = 1e-9 * cell + 16.0 * np.finfo(np.float64).eps * scale
    x0, y0 = float(lo[0]), float(lo[1])
    cell_start, cell_segments = _build_csr(segments, x0, y0, cell, nx, ny, tol)
    return SegmentIndex(x0, y0, cell, int(nx), int(ny), cell_start, cell_segments,
                        np.zeros(m, np.int64), np.zeros(1, np.int64))


def segments_near_box(index: SegmentIndex, lo, hi) -> np.ndarray:
    """The segments near the box lo = (x, y) .. hi = (x, y): (k,) int64, ascending, unique.

    Every segment meeting the box is included (see segments_near)."""
    out = np.empty(len(index.mark), np.int64)
    count = segments_near(index, float(lo[0]), float(lo[1]), float(hi[0]), float(hi[1]), out)
    return out[:count].copy()
