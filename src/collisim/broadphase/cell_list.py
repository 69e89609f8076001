"""The event-driven method's cell grid (cells.py) answering the broad-phase protocol.

ccd keeps every body in the cell holding its centre, with cells at least as wide as the
largest body, in linked lists it can update in O(1) when a body crosses into another cell.
The same structure answers the three questions of a broad phase, for boxes lo, hi:

* pairs: two boxes can overlap only if their centres are within one cell of each other
  (cells are at least as wide as the largest box), so each box looks at the 3 × 3 block of
  cells around its own;
* query: a box overlapping the query box has its centre within the query box grown by half
  the largest box, so only the cells under that grown box are looked at;
* raycast: likewise for the part of the ray inside the grid, grown by half the largest box.
  (Cells are wide here, about one body each, so the bounding box of the ray's part holds few
  more cells than the ray itself crosses.)

It is not a broad phase the discrete step can choose (broadphase.NAMES): the discrete step
rebuilds its structure every step, which the linked lists are not made for.
"""
import numpy as np

from ..core.compiling import compiled, kernel
from ._common import (BroadPhase, bounding_box, boxes_overlap, new_pair_buffer, overlapping_in_run, push_index,
                      push_pair)
from ._rays import clip_to_slab, hits_in_run, new_hit_buffers
from .cells import assign_all, cell_at, make_grid, neighbour_block


def _build(lo, hi):
    """A cell grid over the boxes (n >= 1) with every box filed by its centre, and half the
    largest box's extent."""
    half = float(np.max(hi - lo)) / 2
    corner_lo, corner_hi = bounding_box(lo, hi)
    # a grid needs some width, even for boxes that all coincide far from the origin
    pad = np.maximum(np.maximum(corner_hi - corner_lo, 1.0) * 1e-9,
                     4 * np.spacing(np.maximum(np.abs(corner_lo), np.abs(corner_hi))))
    grid_box = np.concatenate([corner_lo - pad, corner_hi + pad])
    grid = make_grid(grid_box, np.full(len(lo), max(half, 1e-300)), np.zeros((0, 4)))
    assign_all(grid, 0.5 * lo + 0.5 * hi)
    return grid, half


@compiled
def cell_list_pairs(grid, lo, hi):
    """Overlapping pairs (k, 2) intp, i < j, each once: every box against the boxes of the
    3 × 3 block of cells around its own."""
    pairs, count = new_pair_buffer(lo.shape[0]), np.intp(0)
    for i in range(lo.shape[0]):
        cx_lo, cx_hi, cy_lo, cy_hi = neighbour_block(grid, grid.cell[i])
        for cy in range(cy_lo, cy_hi):
            for cx in range(cx_lo, cx_hi):
                j = grid.head[cy * grid.nx + cx]
                while j >= 0:
                    if j > i and boxes_overlap(lo, hi, i, j):
                        pairs, count = push_pair(pairs, count, i, j)
                    j = grid.next[j]
    return pairs[:count]


@kernel
def _cell_range(grid, x0, y0, x1, y1):
    """Column and row ranges (cx_lo, cx_hi, cy_lo, cy_hi), ends exclusive, of the cells under
    the box [x0, x1] × [y0, y1], one more on every side (a centre rounded onto a cell edge may
    be filed in the next cell), clamped to the grid."""
    first, last = cell_at(grid, x0, y0), cell_at(grid, x1, y1)
    return (max(first % grid.nx - 1, 0), min(last % grid.nx + 2, grid.nx),
            max(first // grid.nx - 1, 0), min(last // grid.nx + 2, grid.ny))


@compiled
def _boxes_in_cells(grid, cx_lo, cx_hi, cy_lo, cy_hi):
    """The boxes filed in the cells of the column and row ranges: (boxes (k,) intp, cells)."""
    boxes, count = np.empty(16, np.intp), np.intp(0)
    for cy in range(cy_lo, cy_hi):
        for cx in range(cx_lo, cx_hi):
            i = grid.head[cy * grid.nx + cx]
            while i >= 0:
                boxes, count = push_index(boxes, count, i)
                i = grid.next[i]
    return boxes[:count], (cx_hi - cx_lo) * (cy_hi - cy_lo)


@compiled
def cell_list_query(grid, lo, hi, half, qx0, qy0, qx1, qy1):
    """Boxes overlapping the query box: (found (k,) intp, cells visited, boxes tested)."""
    candidates, visited = _boxes_in_cells(grid, *_cell_range(grid, qx0 - half, qy0 - half, qx1 + half, qy1 + half))
    found, count = overlapping_in_run(lo, hi, candidates, 0, len(candidates), qx0, qy0, qx1, qy1,
                                      np.empty(16, np.intp), 0)
    return found[:count], visited, len(candidates)


@compiled
def cell_list_raycast(grid, lo, hi, half, ox, oy, ux, uy, max_distance):
    """Boxes the ray meets: (found (k,) intp, t_enter (k,), cells visited, boxes tested)."""
    (found, t_enter), count = new_hit_buffers(), np.intp(0)
    x0, y0 = grid.x0 - half, grid.y0 - half
    x1, y1 = grid.x0 + grid.nx * grid.cell_w + half, grid.y0 + grid.ny * grid.cell_h + half
    enter, leave = clip_to_slab(0.0, max_distance, ox, ux, x0, x1)   # the ray's part over the grid
    enter, leave = clip_to_slab(enter, leave, oy, uy, y0, y1)
    if enter > leave:
        return found[:0], t_enter[:0], 0, 0
    ax, ay, bx, by = ox + enter * ux, oy + enter * uy, ox + leave * ux, oy + leave * uy
    candidates, visited = _boxes_in_cells(grid, *_cell_range(grid, min(ax, bx) - half, min(ay, by) - half,
                                                             max(ax, bx) + half, max(ay, by) + half))
    found, t_enter, count = hits_in_run(lo, hi, candidates, 0, len(candidates), ox, oy, ux, uy, max_distance,
                                        found, t_enter, count)
    return found[:count], t_enter[:count], visited, len(candidates)


class CellList(BroadPhase):
    """ccd's cell grid (linked lists by centre), rebuilt for every call."""

    name = "cells"

    def _find(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        grid, _ = _build(lo, hi)
        self.stats.update(shape=(grid.nx, grid.ny))
        return cell_list_pairs(grid, lo, hi)

    def _query(self, lo, hi, qx0, qy0, qx1, qy1):
        grid, half = _build(lo, hi)
        return cell_list_query(grid, lo, hi, half, qx0, qy0, qx1, qy1)

    def _raycast(self, lo, hi, ox, oy, ux, uy, max_distance):
        grid, half = _build(lo, hi)
        return cell_list_raycast(grid, lo, hi, half, ox, oy, ux, uy, max_distance)
