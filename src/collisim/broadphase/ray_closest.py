"""The closest body a ray hits, found by each broad phase in its own way.

BroadPhase.raycast lists every box a ray passes; a ray query wants only the first body it
hits, and each structure can stop early once it knows nothing further along can be closer.
Each traversal below takes the best hit so far (walls and statics may already have given
one), tests bodies exactly (ray_hit.test_body) as it meets them, and prunes with
ray_hit.search_limit, which shrinks as hits are found:

* brute:       every body, exactly;
* sweep_prune: the boxes sorted by their start on the sweep axis; a binary search finds the
  first box that can reach the origin, and the run ends at the first box that starts beyond
  the limit (travelling down the axis: walks down until the boxes' reach falls short of it);
* grid:        the cells along the ray in order (grid_cursor), until the next cell starts
  beyond the limit;
* kdtree, bvh: depth first, the nearer child first; a node popped from the stack is skipped
  if the ray enters it beyond the limit (which may have shrunk since it was pushed).

Each returns (best, visited, tested): the nodes, cells or boxes it examined and the bodies it
tested exactly. The state each needs is a namedtuple, registered with its broad phase in
registry.py; `body_ray_closest(state, ...)` picks the kernel by the state's type when the
caller is compiled, as for the pairs, so one compiled ray loop serves every broad phase and
each choice is cached apart.
"""
from collections import namedtuple

import numpy as np

from ..core.compiling import compiled, kernel
from ._common import bounding_box
from ._rays import farther_then_nearer, ray_box_entry
from .bvh import BoundingVolumeHierarchy, build_bvh, node_entry
from .grid import UniformGrid, cell_bounds
from .grid_cursor import begin_walk, cell_bounds_both_ways, next_cell
from .kdtree import KDTree, build_kdtree, split_region
from .ray_hit import search_limit, test_body, test_run
from .sweep_prune import sorted_intervals, sweep_axis

BruteRays = namedtuple("BruteRays", ["n"])
SweepRays = namedtuple("SweepRays", ["order", "axis", "starts", "reach"])
GridRays = namedtuple("GridRays", ["cell_start", "cell_boxes", "bounds"])
KDTreeRays = namedtuple("KDTreeRays", ["node_axis", "node_value", "node_left", "node_first",
                                       "node_count", "leaf_boxes", "root"])
BVHRays = namedtuple("BVHRays", ["order", "node_lo", "node_hi", "node_first", "node_count",
                                 "node_left"])


def sweep_rays(lo, hi) -> SweepRays:
    """The boxes in sweep order on SweepAndPrune's axis, with their starts and reach."""
    axis = sweep_axis(lo, hi)
    order = np.argsort(lo[:, axis], kind="stable")
    return SweepRays(order, axis, *sorted_intervals(lo, hi, order, axis))


def grid_rays(lo, hi) -> GridRays:
    """The uniform grid exactly as UniformGrid lays it out and fills it, and the cell bounds
    its ray walk uses."""
    origin, cell_size, (nx, ny), cell_start, cell_boxes = UniformGrid()._bin(lo, hi)
    _, corner_hi = bounding_box(lo, hi)
    columns = cell_bounds(origin[0], cell_size, 1.0 / cell_size, nx, corner_hi[0])
    rows = cell_bounds(origin[1], cell_size, 1.0 / cell_size, ny, corner_hi[1])
    return GridRays(cell_start, cell_boxes, cell_bounds_both_ways(*columns, *rows))


def kdtree_rays(lo, hi) -> KDTreeRays:
    """The k-d tree with KDTree's default options, and its root region (the boxes' bounds)."""
    options = KDTree()
    (x0, y0), (x1, y1) = bounding_box(lo, hi)
    return KDTreeRays(*build_kdtree(lo, hi, options.leaf_size, options.max_depth), (x0, y0, x1, y1))


def bvh_rays(lo, hi) -> BVHRays:
    """The BVH with BoundingVolumeHierarchy's default leaf size."""
    return BVHRays(*build_bvh(lo, hi, BoundingVolumeHierarchy().leaf_size)[:6])


# ------------------------------------------------------------ the traversals

@kernel
def brute_ray_closest(state, bodies, ray, best):
    """Every body, tested exactly."""
    for i in range(state.n):
        best = test_body(bodies, i, ray, best)
    return best, state.n, state.n


@kernel
def sweep_run(state, o, u):
    """Where the run of candidate boxes starts and ends (exclusive) in sweep order, and the
    step (+1 up the order, -1 down it). o, u: the ray's origin and direction on the sweep axis.
    Up: from the first box that reaches o. Down: from the last box that starts at or before o.
    Across the axis (u = 0): the boxes whose interval holds o."""
    if u > 0.0:
        return np.searchsorted(state.reach, o, side="left"), state.order.shape[0], 1
    if u < 0.0:
        return np.searchsorted(state.starts, o, side="right") - 1, -1, -1
    return np.searchsorted(state.reach, o, side="left"), np.searchsorted(state.starts, o, side="right"), 1


@kernel
def sweep_ray_closest(state, bodies, ray, best):
    """The run of boxes the ray's span on the sweep axis crosses, stopping at the limit.

    Up the axis the boxes start ever later: stop at the first that starts beyond the limit.
    Down the axis, reach (the furthest end so far) falls: stop when it ends before the ray
    gets there. Crossing times come from the same division as the slab test's."""
    o, u = (ray.ox, ray.ux) if state.axis == 0 else (ray.oy, ray.uy)
    p, end, step = sweep_run(state, o, u)
    visited = 0
    while p != end:
        limit = search_limit(best, ray)
        edge = state.starts[p] if step > 0 else state.reach[p]
        if u != 0.0 and (edge - o) / u > limit:
            break
        visited += 1
        best = test_body(bodies, state.order[p], ray, best)
        p += step
    return best, visited, visited


@kernel
def grid_ray_closest(state, bodies, ray, best):
    """The cells along the ray, in order, until the next one starts beyond the limit."""
    ny = state.bounds.rows[0].shape[0]
    walk, position = begin_walk(state.bounds, ray, search_limit(best, ray))
    visited = tested = 0
    while True:
        ix, iy, position = next_cell(walk, position, search_limit(best, ray))
        if ix < 0:
            return best, visited, tested
        cell = ix * ny + iy  # bin_boxes' numbering
        visited += 1
        best, tested = test_run(bodies, state.cell_boxes, state.cell_start[cell], state.cell_start[cell + 1], ray,
                                best, tested)


@compiled
def kdtree_ray_closest(state, bodies, ray, best):
    """Depth first from the root region (the boxes' bounding box), nearer child first."""
    visited, tested = 1, 0
    t_root = ray_box_entry(ray.ox, ray.oy, ray.ux, ray.uy, search_limit(best, ray), *state.root)
    stack = [(0, state.root, t_root)]
    if t_root == np.inf:
        stack.pop()
    while len(stack) > 0:
        node, region, t_enter = stack.pop()
        limit = search_limit(best, ray)
        if t_enter > limit:
            continue  # a closer hit was found since this node was pushed
        axis = state.node_axis[node]
        if axis < 0:
            first = state.node_first[node]
            best, tested = test_run(bodies, state.leaf_boxes, first, first + state.node_count[node], ray, best, tested)
            continue
        # As in kdtree_raycast: a split value outside the region cuts at its nearest side.
        value = min(max(state.node_value[node], region[axis]), region[axis + 2])
        left_region, right_region = split_region(region, axis, value)
        t_left = ray_box_entry(ray.ox, ray.oy, ray.ux, ray.uy, limit, *left_region)
        t_right = ray_box_entry(ray.ox, ray.oy, ray.ux, ray.uy, limit, *right_region)
        visited += 2
        left = state.node_left[node]
        regions, times = (left_region, right_region), (t_left, t_right)
        far, far_reached, near, near_reached = farther_then_nearer(t_left, t_right)
        if far_reached:
            stack.append((left + far, regions[far], times[far]))
        if near_reached:
            stack.append((left + near, regions[near], times[near]))
    return best, visited, tested


@compiled
def bvh_ray_closest(state, bodies, ray, best):
    """Depth first from the root box, nearer child first."""
    visited, tested = 1, 0
    t_root = node_entry(state.node_lo, state.node_hi, 0, ray.ox, ray.oy, ray.ux, ray.uy,
                        search_limit(best, ray))
    stack = [(0, t_root)]
    if t_root == np.inf:
        stack.pop()
    while len(stack) > 0:
        node, t_enter = stack.pop()
        limit = search_limit(best, ray)
        if t_enter > limit:
            continue  # a closer hit was found since this node was pushed
        left = state.node_left[node]
        if left < 0:
            first = state.node_first[node]
            best, tested = test_run(bodies, state.order, first, first + state.node_count[node], ray, best, tested)
            continue
        t_left = node_entry(state.node_lo, state.node_hi, left, ray.ox, ray.oy, ray.ux, ray.uy, limit)
        t_right = node_entry(state.node_lo, state.node_hi, left + 1, ray.ox, ray.oy, ray.ux, ray.uy, limit)
        visited += 2
        times = (t_left, t_right)
        far, far_reached, near, near_reached = farther_then_nearer(t_left, t_right)
        if far_reached:
            stack.append((left + far, times[far]))
        if near_reached:
            stack.append((left + near, times[near]))
    return best, visited, tested


def body_ray_closest(state, bodies, ray, best):
    """(best, visited, tested) after searching the bodies with the broad phase whose state this
    is (compiled code only; registry.py picks the kernel by the state's type). bodies: as for
    ray_hit.test_body."""
    raise NotImplementedError("body_ray_closest is called from compiled code")
