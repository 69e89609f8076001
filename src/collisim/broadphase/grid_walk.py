"""Walking a ray through the uniform grid, cell by cell (Amanatides & Woo).

A ray crosses the grid's column edges one after another, and its row edges
one after another. Amanatides and Woo's walk keeps, for each axis, the time
t at which the ray leaves the current column (tMaxX) and the current row
(tMaxY), and steps into the next column or row, whichever comes first. The
cells come out in the order the ray meets them, and only they are looked at:
a ray across a grid of n cells visits about sqrt(n) of them.

Here the walk is written column by column: in each column, step up the rows
while the ray reaches the next row no later than it leaves the column
(tMaxY <= tMaxX), then step to the next column. Three details keep it exact:

* Ties. If the ray passes exactly through a cell corner (tMaxY == tMaxX), all
  four cells around the corner touch it, and a box in any of them may touch
  the ray there; so a column's rows start at the first row the ray is still
  in when it enters the column, which may be the row it just left.
* Crossing times come from the cell bounds every time, with the slab test's
  own crossing(), rather than by adding tDelta (repeated additions drift).
  The bounds (grid.cell_bounds) hold every point cell_of files in the cell,
  so rounding in cell_of never puts a box where the walk does not look.
* Mirroring. A ray travelling towards -x sees the columns in the order
  nx - 1, ..., 0. Negating the x coordinates turns that into the +x case
  without changing a single crossing time: (-e - (-o)) / -u == (e - o) / u
  exactly. So the walk is written for directions >= 0 only.

The walk starts where the ray enters the boxes' bounding box and stops at
max_distance or where it leaves the grid.
"""

import numpy as np

from ..core.compiling import compiled, kernel
from ._rays import crossing, hits_in_run, new_hit_buffers, ray_box_entry


@compiled
def travel_axis(starts, ends, o, u):
    """One axis as the ray sees it: the cells' starts and ends (n,) in the
    order the ray meets them, and its coordinate and direction (>= 0) along
    the axis. For u < 0 the axis is mirrored (x -> -x): cell k becomes
    n - 1 - k, its end becomes its start."""
    if u >= 0:
        return starts, ends, o, u
    return -ends[::-1], -starts[::-1], -o, -u


@kernel
def slab_times(starts, ends, o, u, k):
    """(enter, leave): when the ray is inside slab k, starts[k] <= coordinate
    <= ends[k], on a travel axis (u >= 0). enter > leave if never."""
    if u > 0:
        return crossing(o, u, starts[k]), crossing(o, u, ends[k])
    if starts[k] <= o <= ends[k]:
        return -np.inf, np.inf  # running along the slab: inside all the time
    return np.inf, -np.inf


@kernel
def first_slab(ends, o, u, t):
    """The first slab (in travel order) the ray is still in at time t: the
    first k it leaves at or after t. ends (n,) on a travel axis; a binary
    search, since leave times grow with k (for u == 0: the first slab that
    reaches the ray's line)."""
    low, high = 0, ends.shape[0] - 1
    while low < high:
        mid = (low + high) // 2
        if (crossing(o, u, ends[mid]) >= t) if u > 0 else (ends[mid] >= o):
            high = mid
        else:
            low = mid + 1
    return low


@compiled
def grid_raycast(lo, hi, cell_start, cell_boxes, column_starts, column_ends, row_starts, row_ends,
                 ox, oy, ux, uy, max_distance):
    """Boxes the ray meets, testing only those filed in the cells it passes.

    lo, hi: (n, 2); cell_start, cell_boxes: from bin_boxes; column_starts,
    column_ends (nx,) and row_starts, row_ends (ny,): from cell_bounds.
    Returns found (k,) intp and t_enter (k,) float64 (a box spanning several
    cells may appear more than once), the number of cells visited, and the
    number of boxes tested.
    """
    nx, ny = column_starts.shape[0], row_starts.shape[0]
    (found, t_enter), count = new_hit_buffers(), np.intp(0)
    visited = tested = 0
    start = ray_box_entry(ox, oy, ux, uy, max_distance, column_starts[0], row_starts[0],
                          column_ends[nx - 1], row_ends[ny - 1])
    if start == np.inf:
        return found[:0], t_enter[:0], visited, tested  # misses every box's cells
    x_starts, x_ends, px, vx = travel_axis(column_starts, column_ends, ox, ux)
    y_starts, y_ends, py, vy = travel_axis(row_starts, row_ends, oy, uy)
    column = first_slab(x_ends, px, vx, start)
    row = first_slab(y_ends, py, vy, start)
    while column < nx and row < ny:
        column_enter, column_leave = slab_times(x_starts, x_ends, px, vx, column)
        enter, leave = max(start, column_enter), min(max_distance, column_leave)
        if enter > leave:
            break  # this column (and every later one) lies beyond max_distance
        # Skip the rows the ray left before entering this column.
        while row < ny and slab_times(y_starts, y_ends, py, vy, row)[1] < enter:
            row += 1
        # Visit the rows it passes while in the column: those it reaches by
        # the time it leaves (tMaxY <= tMaxX; equal at a corner).
        r = row
        while r < ny and slab_times(y_starts, y_ends, py, vy, r)[0] <= leave:
            ix = column if ux >= 0 else nx - 1 - column
            iy = r if uy >= 0 else ny - 1 - r
            cell = ix * ny + iy
            visited += 1
            tested += cell_start[cell + 1] - cell_start[cell]
            found, t_enter, count = hits_in_run(lo, hi, cell_boxes, cell_start[cell], cell_start[cell + 1],
                                                ox, oy, ux, uy, max_distance, found, t_enter, count)
            r += 1
        column += 1
    return found[:count], t_enter[:count], visited, tested
