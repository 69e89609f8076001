"""Bounding volume hierarchy: group the objects, not the space.

A k-d tree cuts *space* and lets an object sit on both sides of a cut. A BVH
partitions the *objects* instead: every object lives in exactly one leaf.
Building top-down, a node takes its objects, sorts them by centre along the
axis where the centres spread widest, and hands the first half to its left
child and the second half to its right child (a median split of the objects;
the code finds the median without a full sort, see ``split_in_half``; the
tree lives in flat arrays allocated once per build, see ``build_bvh``).
Each node stores the tight box around its objects, so sibling boxes may
overlap — that is the price of never duplicating an object. A node with at
most ``leaf_size`` objects is a leaf.

Finding pairs is a traversal of the tree against itself:

* a node against itself: its two children against themselves, and the left
  child against the right child (a leaf against itself tests its objects
  pairwise);
* node A against a different node B: only if their boxes overlap — otherwise
  nothing below A can touch anything below B and the whole branch is pruned.
  Two leaves test their objects; else the larger node is opened up.

Each pair of objects is met exactly once, in the unique node where their
paths from the root part.

A box query or a ray cast is a traversal of the tree from the root: enter a
node only if its box overlaps the query box (or the ray reaches its box
within max_distance; nearer child first). A node's box holds all its
objects' boxes, so nothing below a node that is missed can be hit.
"""

import numpy as np

from ..core.compiling import compiled, kernel
from ._common import (BroadPhase, box_meets_query, boxes_overlap, check_boxes, check_int_option, copy_row,
                      gathered_boxes, new_pair_buffer, overlapping_in_run, push_pair, row_centre, select_smallest, widest_axis)
from ._rays import farther_then_nearer, hits_in_run, new_hit_buffers, ray_box_entry


@kernel
def split_in_half(order, rows, first, count, axis, keys, moved, moved_rows):
    """Reorder the run [first, first + count) of order (box indices) and rows (their boxes,
    gathered_boxes) so the count // 2 boxes with the smallest centres on `axis` come first.

    keys, moved: (n,) and moved_rows (n, 4): scratch. This is "sort by centre and cut the
    list in half", except that we only need to know which half each box falls in: finding
    the median (select_smallest) takes linear time where sorting takes m log m. Boxes whose
    centre equals the median fill up the lower half in their current order, and both
    halves keep the run's order otherwise.
    """
    half = count // 2
    for k in range(count):
        keys[k] = row_centre(rows, first + k, axis)
    select_smallest(keys, count, half)
    median = keys[half]
    ties_for_lower = half
    for k in range(first, first + count):
        ties_for_lower -= row_centre(rows, k, axis) < median
    lower, upper = 0, half
    for k in range(first, first + count):
        key = row_centre(rows, k, axis)
        if key < median or (key == median and ties_for_lower > 0):
            if key == median:
                ties_for_lower -= 1
            to = lower
            lower += 1
        else:
            to = upper
            upper += 1
        moved[to] = order[k]
        copy_row(rows, k, moved_rows, to)
    for k in range(count):
        order[first + k] = moved[k]
        copy_row(moved_rows, k, rows, first + k)


@kernel
def fit_boxes(rows, node_first, node_count, node_left, node_lo, node_hi):
    """Each node's tight box: a leaf's around its rows (gathered_boxes, in order's order),
    any other node's around its two children's (numbered after it, so done first)."""
    for node in range(node_first.shape[0] - 1, -1, -1):
        left = node_left[node]
        if left >= 0:
            for axis in range(2):
                node_lo[node, axis] = min(node_lo[left, axis], node_lo[left + 1, axis])
                node_hi[node, axis] = max(node_hi[left, axis], node_hi[left + 1, axis])
            continue
        node_lo[node], node_hi[node] = np.inf, -np.inf
        for k in range(node_first[node], node_first[node] + node_count[node]):
            for axis in range(2):
                node_lo[node, axis] = min(node_lo[node, axis], rows[k, axis])
                node_hi[node, axis] = max(node_hi[node, axis], rows[k, axis + 2])


@compiled
def build_bvh(lo, hi, leaf_size):
    """Build the tree top-down by median object splits, into arrays allocated once.

    lo, hi: (n, 2), n >= 1. Returns, for m <= 2n - 1 nodes numbered depth-first:
    order (n,): box indices, each node's boxes being one contiguous run of it;
    node_lo, node_hi (m, 2): the tight box around each node's boxes;
    node_first, node_count (m,): the node's run is order[first:first + count];
    node_left (m,): the left child (the right child is left + 1), -1 for a leaf;
    node_depth (m,).
    Splitting a node only reorders its run of `order`, and of the boxes gathered beside it
    (through scratch arrays of n): nothing is allocated per node.
    """
    n = lo.shape[0]
    order, rows = np.arange(n), gathered_boxes(lo, hi)
    keys, moved, moved_rows = np.empty(n), np.empty(n, np.intp), np.empty((n, 4))
    capacity = 2 * n - 1  # a binary tree with at most n leaves
    node_first = np.zeros(capacity, np.intp)
    node_count = np.zeros(capacity, np.intp)
    node_left = np.full(capacity, -1, np.intp)
    node_depth = np.zeros(capacity, np.intp)
    node_count[0] = n
    n_nodes = 1
    # Depth first, left child first: at most one pending right child per level, and a
    # median split makes at most log2(n) + 1 levels.
    stack = np.empty(66, np.intp)
    stack[0], pending = 0, 1
    while pending > 0:
        pending -= 1
        node = stack[pending]
        first, count = node_first[node], node_count[node]
        if count <= leaf_size:
            continue
        # Split the boxes at their median centre on the axis of widest
        # spread and give each child one half.
        axis = widest_axis(rows[first:first + count])
        split_in_half(order, rows, first, count, axis, keys, moved, moved_rows)
        half = count // 2
        left = n_nodes
        n_nodes += 2
        node_left[node] = left
        node_first[left], node_count[left] = first, half
        node_first[left + 1], node_count[left + 1] = first + half, count - half
        node_depth[left] = node_depth[left + 1] = node_depth[node] + 1
        stack[pending], stack[pending + 1] = left + 1, left
        pending += 2
    node_lo, node_hi = np.empty((n_nodes, 2)), np.empty((n_nodes, 2))
    fit_boxes(rows, node_first[:n_nodes], node_count[:n_nodes], node_left[:n_nodes], node_lo, node_hi)
    return (order, node_lo, node_hi, node_first[:n_nodes],
            node_count[:n_nodes], node_left[:n_nodes], node_depth[:n_nodes])


@compiled
def run_pairs(lo, hi, order, first_a, count_a, first_b, count_b, same, pairs, count):
    """Append overlapping pairs between two runs of `order`; `same` means both
    runs are one leaf, tested against itself (each pair once)."""
    for a in range(first_a, first_a + count_a):
        for b in range(a + 1 if same else first_b, first_b + count_b):
            i, j = order[a], order[b]
            if boxes_overlap(lo, hi, i, j):
                pairs, count = push_pair(pairs, count, i, j)
    return pairs, count


@compiled
def bvh_pairs(lo, hi, order, node_lo, node_hi, node_first, node_count, node_left):
    """Overlapping pairs by traversing the tree against itself (arrays from build_bvh).

    Returns (k, 2) intp pairs with i < j.
    """
    pairs, count = new_pair_buffer(lo.shape[0]), np.intp(0)
    stack = [(0, 0)]
    while len(stack) > 0:
        a, b = stack.pop()
        a_left, b_left = node_left[a], node_left[b]
        if a == b and a_left >= 0:
            # A node against itself: both children against themselves, and each other.
            stack.append((a_left, a_left))
            stack.append((a_left + 1, a_left + 1))
            stack.append((a_left, a_left + 1))
        elif a != b and not boxes_overlap(node_lo, node_hi, a, b):
            continue  # disjoint boxes: nothing below a can touch anything below b
        elif a_left < 0 and b_left < 0:
            pairs, count = run_pairs(lo, hi, order, node_first[a], node_count[a],
                                     node_first[b], node_count[b], a == b, pairs, count)
        elif b_left < 0 or (a_left >= 0 and node_count[a] >= node_count[b]):
            stack.append((a_left, b))
            stack.append((a_left + 1, b))
        else:
            stack.append((a, b_left))
            stack.append((a, b_left + 1))
    return pairs[:count]


@compiled
def bvh_query(lo, hi, order, node_lo, node_hi, node_first, node_count, node_left,
              qx0, qy0, qx1, qy1):
    """Boxes overlapping the query box [qx0, qx1] x [qy0, qy1] (arrays from build_bvh).

    Returns (found (k,) intp, nodes visited, boxes tested); every box is in
    one leaf only, so there are no repeats.
    """
    found, count, visited, tested = np.empty(16, np.intp), np.intp(0), 0, 0
    stack = [0]
    while len(stack) > 0:
        node = stack.pop()
        visited += 1
        if not box_meets_query(node_lo, node_hi, node, qx0, qy0, qx1, qy1):
            continue  # nothing below this node reaches the query box
        left = node_left[node]
        if left >= 0:
            stack.append(left + 1)
            stack.append(left)
            continue
        first, end = node_first[node], node_first[node] + node_count[node]
        tested += end - first
        found, count = overlapping_in_run(lo, hi, order, first, end, qx0, qy0, qx1, qy1, found, count)
    return found[:count], visited, tested


@kernel
def node_entry(node_lo, node_hi, node, ox, oy, ux, uy, max_distance):
    """Where the ray enters node's box (inf if it misses)."""
    return ray_box_entry(ox, oy, ux, uy, max_distance,
                         node_lo[node, 0], node_lo[node, 1], node_hi[node, 0], node_hi[node, 1])


@compiled
def bvh_raycast(lo, hi, order, node_lo, node_hi, node_first, node_count, node_left,
                ox, oy, ux, uy, max_distance):
    """Boxes the ray meets (arrays from build_bvh).

    Returns found (k,) intp, t_enter (k,) float64, nodes visited (node boxes
    tested against the ray) and boxes tested.
    """
    (found, t_enter), count = new_hit_buffers(), np.intp(0)
    visited, tested = 1, 0
    stack = [0]
    if node_entry(node_lo, node_hi, 0, ox, oy, ux, uy, max_distance) == np.inf:
        stack.pop()  # the ray misses the root's box, and so every box
    while len(stack) > 0:
        node = stack.pop()
        left = node_left[node]
        if left < 0:
            tested += node_count[node]
            found, t_enter, count = hits_in_run(lo, hi, order, node_first[node], node_first[node] + node_count[node],
                                                ox, oy, ux, uy, max_distance, found, t_enter, count)
            continue
        t_left = node_entry(node_lo, node_hi, left, ox, oy, ux, uy, max_distance)
        t_right = node_entry(node_lo, node_hi, left + 1, ox, oy, ux, uy, max_distance)
        visited += 2
        # The nearer child is searched first; a child whose box the ray misses is pruned
        # with everything below it.
        far, far_reached, near, near_reached = farther_then_nearer(t_left, t_right)
        if far_reached:
            stack.append(left + far)
        if near_reached:
            stack.append(left + near)
    return found[:count], t_enter[:count], visited, tested


class BoundingVolumeHierarchy(BroadPhase):
    """BVH broad phase, rebuilt every frame."""

    name = "bvh"
    OPTIONS = ("leaf_size",)
    EMPTY_STATS = {"nodes": 0, "depth": 0}

    def __init__(self, leaf_size=2):
        super().__init__()
        self.leaf_size = check_int_option("leaf_size", leaf_size, 1)

    def _find(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        order, node_lo, node_hi, first, count, left, depth = build_bvh(lo, hi, self.leaf_size)
        self.stats.update(nodes=len(node_lo), depth=int(depth.max()))
        return bvh_pairs(lo, hi, order, node_lo, node_hi, first, count, left)

    def _query(self, lo, hi, qx0, qy0, qx1, qy1):
        order, node_lo, node_hi, first, count, left, _ = build_bvh(lo, hi, self.leaf_size)
        return bvh_query(lo, hi, order, node_lo, node_hi, first, count, left, qx0, qy0, qx1, qy1)

    def _raycast(self, lo, hi, ox, oy, ux, uy, max_distance):
        order, node_lo, node_hi, first, count, left, _ = build_bvh(lo, hi, self.leaf_size)
        return bvh_raycast(lo, hi, order, node_lo, node_hi, first, count, left,
                           ox, oy, ux, uy, max_distance)

    def describe(self, lo, hi) -> dict:
        """Nodes as (node_lo, node_hi, depth, is_leaf) in depth-first order, the
        leaves' box indices (every box in exactly one leaf), and the pairs."""
        lo, hi = check_boxes(lo, hi)
        if len(lo) == 0:
            return {"nodes": [], "leaves": [], "pairs": self.pairs(lo, hi)}
        order, node_lo, node_hi, first, count, left, depth = build_bvh(lo, hi, self.leaf_size)
        is_leaf = left < 0
        return {
            "nodes": [(node_lo[k], node_hi[k], int(depth[k]), bool(is_leaf[k]))
                      for k in range(len(node_lo))],
            "leaves": [order[first[k]:first[k] + count[k]] for k in np.flatnonzero(is_leaf)],
            "pairs": self.pairs(lo, hi),
        }
