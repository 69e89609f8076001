"""The closest thin segment a ray hits, found through the static segment index.

The ray walks the index's cells in the order it meets them (broadphase/grid_cursor.py) and
tests the segments registered in each exactly (geometry/ray.py), until the next cell starts
beyond the best hit. A segment is registered in every cell its line passes within a tolerance
far above rounding (segment_index.py), and the cell holding a hit point is one the ray passes
at that distance, so the walk cannot miss the closest segment. The same walk serves the world's
segments and the map's contour segments (a different hit kind).
"""
import math
from collections import namedtuple

import numpy as np

from ..broadphase.grid_cursor import begin_walk, cell_bounds_both_ways, next_cell
from ..broadphase.ray_hit import keep_closer, search_limit
from ..core.compiling import compiled, kernel
from ..core.geometry.ray import ray_segment
from ..core.geometry.segment import closest_on_segment
from ..statics.segment_index import build_segment_index

SegmentGrid = namedtuple("SegmentGrid", ["segments", "cell_start", "cell_segments", "bounds"])
SegmentGrid.__doc__ = """m segments (m, 4) and their index as a ray walks it: bounds is a
grid_cursor.CellBounds, and cell (cx, cy) holds the segments
cell_segments[cell_start[c]:cell_start[c + 1]], c = cy * nx + cx (segment_index's numbering)."""


def segment_grid(segments, box) -> SegmentGrid:
    """Index segments (m, 4) rows x0, y0, x1, y1 (build_segment_index, over the box and the
    segments) for ray walks."""
    segments = np.ascontiguousarray(segments, dtype=np.float64).reshape(-1, 4)
    index = build_segment_index(segments, box)
    # The cell edges exactly as segment_index computes them when registering segments.
    columns, rows = np.arange(index.nx), np.arange(index.ny)
    bounds = cell_bounds_both_ways(index.x0 + columns * index.cell, index.x0 + (columns + 1) * index.cell,
                                   index.y0 + rows * index.cell, index.y0 + (rows + 1) * index.cell)
    return SegmentGrid(segments, index.cell_start, index.cell_segments, bounds)


@compiled(inline="always")
def segment_ray_closest(grid, kind, ray, best):
    """Keep the closer of best and the first segment of `grid` the ray hits (hit kind `kind`,
    index the segment's row). ray: a broadphase.ray_hit.Ray."""
    if grid.segments.shape[0] == 0:
        return best
    columns = grid.bounds.columns[0].shape[0]
    walk, position = begin_walk(grid.bounds, ray, search_limit(best, ray))
    while True:
        cx, cy, position = next_cell(walk, position, search_limit(best, ray))
        if cx < 0:
            return best
        cell = cy * columns + cx
        for k in range(grid.cell_start[cell], grid.cell_start[cell + 1]):
            s = grid.cell_segments[k]
            x0, y0, x1, y1 = grid.segments[s, 0], grid.segments[s, 1], grid.segments[s, 2], grid.segments[s, 3]
            t, normal_x, normal_y = ray_segment(ray.ox, ray.oy, ray.ux, ray.uy, x0, y0, x1, y1)
            best = keep_closer(best, t, False, kind, s, normal_x, normal_y, ray.max_distance)


@kernel
def nearest_segment(segments, px, py):
    """The row of the segment (m, 4), m >= 1, closest to the point (the first of equals)."""
    nearest, nearest_distance = 0, np.inf
    for s in range(segments.shape[0]):
        qx, qy, _ = closest_on_segment(px, py, segments[s, 0], segments[s, 1], segments[s, 2], segments[s, 3])
        distance = math.hypot(px - qx, py - qy)
        if distance < nearest_distance:
            nearest, nearest_distance = s, distance
    return nearest
