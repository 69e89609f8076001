"""The broad phases as the discrete step calls them from compiled code, every step.

Each method keeps what it needs between steps in a small state (a namedtuple of arrays and
numbers): sweep and prune its sorted order, the grid its fixed layout over the box and the
scratch of its home-cell filing (grid_home.py), the trees their options.
`candidate_pairs(state, lo, hi)` is one compiled function whose implementation
is chosen by the *type* of the state when the step is compiled (numba's overload, registered
with each broad phase in registry.py), so a run compiles only the broad phase it uses and each
choice is cached on its own.

Every kernel returns pairs (k, 2) intp with i < j, each pair once, containing every pair of
overlapping boxes — in the method's own order: the step puts them in canonical order itself
(sort_pairs, which leaves pairs already in order as they are), as
broadphase/__init__.py's functions do for their callers.
"""
from collections import namedtuple

import numpy as np

from ..core.arrays import stable_order_of_floats
from ..core.compiling import compiled
from .brute import brute_force_pairs
from .bvh import build_bvh, bvh_pairs
from .grid import bin_boxes, grid_pairs
from .grid_home import home_cells_per_unit, home_grid_pairs, home_layout, home_scratch
from .kdtree import kdtree_pairs
from .sweep_prune import repair_order, sweep

BruteState = namedtuple("BruteState", ["n"])
SweepState = namedtuple("SweepState", ["order", "axis"])        # (n,) intp; (1,) intp, -1 before the first sort
GridState = namedtuple("GridState", ["origin", "cells_per_unit", "nx", "ny", "finest", "home_nx", "home_ny",
                                     "count", "start", "ids", "lo", "hi", "room", "homes", "cell_homes"],
                       defaults=(None,) * 11)
GridState.__doc__ = """A fixed grid over the world's box: origin (2,), 1 / cell width, nx x ny cells; the
finest grid home-cell filing may use (grid_home.py's home_layout: 1 / cell width, home_nx x home_ny
cells) and its scratch, made once (home_scratch): count, zero between steps, start, the n boxes in
cell order (ids, lo, hi), room, each box's home cell (homes by index, cell_homes in cell order).
Given the layout alone (the rest None), it serves drawings of the grid (render/structures.py),
not the step."""
I_COLUMN, J_COLUMN = np.int64(0), np.int64(1)   # (numpy integers: one compile for both)
KDTreeState = namedtuple("KDTreeState", ["leaf_size", "max_depth"])
BVHState = namedtuple("BVHState", ["leaf_size"])


def box_grid(box, radii) -> GridState:
    """A fixed grid over the world's box (bodies never leave it): cells twice the median
    diameter, widened so there are at most about 4n cells; and the scratch for filing the
    world's n boxes in home cells as narrow as its largest circle allows (home_layout)."""
    width, height = box[2] - box[0], box[3] - box[1]
    n = len(radii)
    typical = float(np.median(radii)) if n else 0.0   # an empty world: cells from the box alone
    cell = max(4.0 * typical, np.sqrt(width * height / (4 * max(n, 1))))
    nx, ny = int(width // cell) + 1, int(height // cell) + 1
    finest, home_nx, home_ny = home_layout(width, height, cell, float(np.max(radii)) if n else 0.0, n)
    return GridState(np.array(box[:2], np.float64), 1.0 / cell, nx, ny, finest, home_nx, home_ny,
                     *home_scratch(home_nx, home_ny, n))


def sweep_state(world) -> SweepState:
    """Sweep and prune's state before its first sort: the identity order, no axis yet."""
    return SweepState(np.arange(world.n), np.full(1, -1, np.intp))


@compiled
def sort_pairs(pairs, n):
    """Pairs (k, 2) with i < j, each once, in lexicographic (i, j) order: the canonical order
    in which the response treats contacts, whichever broad phase found them. Pairs already in
    that order (brute force finds them so) are returned as they are: sorting the polygons
    pile's 133 pairs costs as much as finding them. Others are sorted by j, then stably by i,
    each a counting sort over the n bodies: two passes over the pairs and two over the bodies,
    where a radix sort of (i * n + j) took a pass for each of the key's bytes."""
    for k in range(1, pairs.shape[0]):
        if pairs[k, 0] < pairs[k - 1, 0] or (pairs[k, 0] == pairs[k - 1, 0] and pairs[k, 1] < pairs[k - 1, 1]):
            return _counting_sort(_counting_sort(pairs, n, J_COLUMN), n, I_COLUMN)
    return pairs


@compiled
def _counting_sort(pairs, n, column):
    """The rows of pairs (k, 2) stably ordered by their value in `column` (0 .. n - 1)."""
    start = np.zeros(n + 1, np.int64)
    for p in range(pairs.shape[0]):
        start[pairs[p, column] + 1] += 1
    for value in range(n):
        start[value + 1] += start[value]
    out = np.empty_like(pairs)
    for p in range(pairs.shape[0]):
        row = start[pairs[p, column]]
        start[pairs[p, column]] = row + 1
        out[row, 0], out[row, 1] = pairs[p, 0], pairs[p, 1]
    return out


# Plain functions: registry.py hands the state's kernel to numba as candidate_pairs'
# implementation, so each is compiled once, inside the step (a jitted kernel behind a jitted
# wrapper was two compiles, about a second more on a first run).
def brute_pairs(state, lo, hi):
    return brute_force_pairs(lo, hi)


@compiled
def _sweep_axis(lo, hi):
    """The axis (0 or 1) along which the box centres have the larger variance."""
    n = lo.shape[0]
    spread = np.zeros(2)
    for axis in range(2):
        mean = 0.0
        for i in range(n):
            mean += lo[i, axis] + hi[i, axis]
        mean /= n
        for i in range(n):
            d = lo[i, axis] + hi[i, axis] - mean
            spread[axis] += d * d
    return 1 if spread[1] > spread[0] else 0


def sweep_pairs(state, lo, hi):
    n = lo.shape[0]
    axis = _sweep_axis(lo, hi)
    keys = lo[:, axis].copy()
    # Last step's order is nearly sorted: repair it by insertion sort, unless the axis
    # changed or the repair would cost more than a fresh n log n sort.
    if axis != state.axis[0] or repair_order(keys, state.order, n * int(np.ceil(np.log2(n)))) < 0:
        state.order[:] = stable_order_of_floats(keys)
        state.axis[0] = axis
    return sweep(lo, hi, state.order, axis)


def grid_step_pairs(state, lo, hi):
    # Each box filed once, in its home cell, and the boxes gathered into cell order (grid_home.py),
    # in cells as wide as the widest box, when that is at most twice the grid's own cells and the
    # scratch holds the boxes; otherwise each box in every cell it overlaps (grid.py).
    n = lo.shape[0]
    per_unit = home_cells_per_unit(lo, hi, state.finest, state.cells_per_unit) if n <= state.ids.shape[0] else 0.0
    if per_unit > 0.0:
        scale = per_unit / state.finest   # at most 1: no more cells than the scratch's grid
        nx, ny = min(state.home_nx, int(state.home_nx * scale) + 1), min(state.home_ny, int(state.home_ny * scale) + 1)
        return home_grid_pairs(lo, hi, state.origin, per_unit, nx, ny, state.count, state.start, state.ids,
                               state.lo, state.hi, state.room, state.homes, state.cell_homes)
    start, boxes = bin_boxes(lo, hi, state.origin, state.cells_per_unit, state.nx, state.ny)
    return grid_pairs(lo, hi, state.origin, state.cells_per_unit, state.nx, state.ny, start, boxes)


def kdtree_step_pairs(state, lo, hi):
    return kdtree_pairs(lo, hi, state.leaf_size, state.max_depth)[0]


def bvh_step_pairs(state, lo, hi):
    order, node_lo, node_hi, first, count, left, _ = build_bvh(lo, hi, state.leaf_size)
    return bvh_pairs(lo, hi, order, node_lo, node_hi, first, count, left)


def candidate_pairs(state, lo, hi):
    """Candidate pairs of boxes lo, hi (n, 2), n >= 2, for the broad phase whose state this is
    (compiled code only; registry.py picks the kernel by the state's type)."""
    raise NotImplementedError("candidate_pairs is called from compiled code")
