"""The Amanatides–Woo walk of grid_walk.py, one cell at a time, for searches that stop early.

grid_raycast walks every cell up to max_distance. A closest-hit search wants the cells one by
one, in the order the ray meets them, and a limit that shrinks as hits are found: once the next
cell starts beyond the best hit, nothing further along can beat it. The cursor here is the same
walk (column by column; in each column the rows the ray passes before it leaves the column;
ties at a corner visit all four cells; the same travel_axis, slab_times and first_slab) with
its loop turned inside out: `next_cell` returns one cell and where to resume.

The grid is given by the bounds of its columns and rows (ascending starts and ends, each cell
closed; grid.cell_bounds, or the static segment index's cell edges), so the body grid and the
segment index share the walk; each caller turns (column, row) into its own cell id. The
mirrored bounds a ray travelling towards -x or -y walks (travel_axis) are made once per grid,
not once per ray: allocating them took most of a short walk's time.
"""
from collections import namedtuple

import numpy as np

from ..core.compiling import compiled, kernel
from ._rays import ray_box_entry
from .grid_walk import first_slab, slab_times, travel_axis

CellBounds = namedtuple("CellBounds", ["columns", "rows", "mirrored_columns", "mirrored_rows"])
CellBounds.__doc__ = """A grid's cells as a ray walks them: columns = (starts (nx,), ends (nx,)),
rows likewise (ny,), and each mirrored (x -> -x: travel_axis's order for a negative direction)."""


def cell_bounds_both_ways(column_starts, column_ends, row_starts, row_ends) -> CellBounds:
    """CellBounds from the columns' and rows' ascending starts and ends."""
    columns = (np.ascontiguousarray(column_starts, np.float64), np.ascontiguousarray(column_ends, np.float64))
    rows = (np.ascontiguousarray(row_starts, np.float64), np.ascontiguousarray(row_ends, np.float64))
    mirrored_columns = tuple(np.ascontiguousarray(a) for a in travel_axis(*columns, 0.0, -1.0)[:2])
    mirrored_rows = tuple(np.ascontiguousarray(a) for a in travel_axis(*rows, 0.0, -1.0)[:2])
    return CellBounds(columns, rows, mirrored_columns, mirrored_rows)


@compiled(inline="always")
def travel(bounds, mirrored, o, u):
    """One axis in the order the ray meets its cells, as travel_axis gives it: the starts and
    ends, and the ray's coordinate and direction (>= 0) along it."""
    if u >= 0.0:
        return bounds[0], bounds[1], o, u
    return mirrored[0], mirrored[1], -o, -u


@compiled
def begin_walk(bounds, ray, limit):
    """A cursor for the ray over the grid: (walk, position) for next_cell.

    bounds: CellBounds; ray: a ray_hit.Ray; limit: the farthest distance of interest. walk
    holds each axis in travel order and the time the ray enters the grid; position is
    (column, row, next row to visit, the column's leave time), in travel order.
    """
    (column_starts, column_ends), (row_starts, row_ends) = bounds.columns, bounds.rows
    nx, ny = column_starts.shape[0], row_starts.shape[0]
    start = ray_box_entry(ray.ox, ray.oy, ray.ux, ray.uy, limit, column_starts[0], row_starts[0],
                          column_ends[nx - 1], row_ends[ny - 1])
    x_starts, x_ends, px, vx = travel(bounds.columns, bounds.mirrored_columns, ray.ox, ray.ux)
    y_starts, y_ends, py, vy = travel(bounds.rows, bounds.mirrored_rows, ray.oy, ray.uy)
    walk = (x_starts, x_ends, px, vx, ray.ux < 0.0, y_starts, y_ends, py, vy, ray.uy < 0.0, start)
    if start == np.inf:
        return walk, (nx, ny, ny, -np.inf)  # misses the grid: nothing to visit
    # Just before the first column, with no rows left in it: next_cell steps into it.
    return walk, (first_slab(x_ends, px, vx, start) - 1, first_slab(y_ends, py, vy, start), ny, -np.inf)


@kernel
def next_cell(walk, position, limit):
    """The next cell the ray meets no later than limit: (column, row, position), column and row
    in the grid's own numbering, or column -1 when the walk is over. limit may shrink between
    calls, never grow."""
    x_starts, x_ends, px, vx, flip_x, y_starts, y_ends, py, vy, flip_y, start = walk
    nx, ny = x_starts.shape[0], y_starts.shape[0]
    column, row, r, leave = position
    while True:
        # The next row of this column, if the ray reaches it before leaving the column.
        if r < ny and slab_times(y_starts, y_ends, py, vy, r)[0] <= min(leave, limit):
            ix = nx - 1 - column if flip_x else column
            iy = ny - 1 - r if flip_y else r
            return ix, iy, (column, row, r + 1, leave)
        column += 1
        if column >= nx or row >= ny:
            return -1, -1, (nx, ny, ny, leave)
        column_enter, column_leave = slab_times(x_starts, x_ends, px, vx, column)
        enter, leave = max(start, column_enter), min(limit, column_leave)
        if enter > leave:
            return -1, -1, (nx, ny, ny, leave)  # this column, and every later one, is too far
        # Skip the rows the ray left before entering this column.
        while row < ny and slab_times(y_starts, y_ends, py, vy, row)[1] < enter:
            row += 1
        r = row
