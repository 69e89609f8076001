"""k-d tree: split space in two at the median, again and again.

Start with one region holding every box. Split it with a line through the
median of the box centres — along the axis where the centres spread widest —
so that half the boxes lie on each side. A box that straddles the line goes
to *both* sides: it could touch boxes on either. Repeat on each side until a
region is a leaf, then test the boxes inside each leaf against each other.

A region becomes a leaf when

* it holds at most ``leaf_size`` boxes, or
* it sits ``max_depth`` splits deep, or
* no split helps: if one side would still hold every box, splitting removes
  nothing (the video's example: two overlapping particles straddle any line
  between them, so both sides would keep both). We then try the other axis,
  and if that fails too the region stays a leaf. Requiring both sides to
  shrink also guarantees that the recursion ends.

The exact split rule: with the node's m centres sorted on the axis, the line
goes halfway between the (m//2)-th and the next one, so the lower half of the
centres is on the left. The left region is ``coordinate < value``, the right
one ``coordinate >= value``; a box goes left if its min is < value and right
if its max is >= value.

Because straddling boxes live in several leaves, a pair can meet in more
than one leaf. Each pair is reported only by the leaf whose region contains
the lower-left corner of the two boxes' intersection: that point lies in
both boxes, so both boxes are in that leaf, and the leaf regions tile the
plane without overlap, so exactly one leaf reports the pair.

For box queries and ray casts, :func:`build_kdtree` makes the same splits
and stores the tree in flat arrays. A query box goes down the tree the way
a box is filed into it: left if its min is < the split value, right if its
max is >= it. A ray goes into the children whose region it reaches within
max_distance, nearer child first.
"""

import numpy as np
from numba import njit

from ..arrays import grown
from ._common import (BroadPhase, bounding_box, boxes_overlap, check_boxes, check_int_option, new_pair_buffer,
                      overlapping_in_run, push_pair, widest_axis)
from ._rays import farther_then_nearer, hits_in_run, new_hit_buffers, ray_box_entry


@njit(cache=True)
def median_split_value(lo, hi, members, axis):
    """Split line on `axis` with the lower half of the members' centres on its left.

    lo, hi: (n, 2); members: (m,) box indices, m >= 2. np.partition puts the
    two middle centres where a sort would (without sorting the rest).
    """
    half = members.shape[0] // 2
    centres = np.partition(0.5 * lo[members, axis] + 0.5 * hi[members, axis], (half - 1, half))
    return 0.5 * centres[half - 1] + 0.5 * centres[half]


@njit(cache=True)
def split_sides(lo, hi, members, axis, value):
    """The members going left (min < value) and right (max >= value); straddlers go both ways."""
    return members[lo[members, axis] < value], members[hi[members, axis] >= value]


@njit(cache=True)
def split_node(lo, hi, members, depth, leaf_size, max_depth):
    """Decide whether and how to split a node.

    lo, hi: (n, 2); members: (m,) indices of the boxes in the node.
    Returns (axis, value, left members, right members), or axis -1 for a leaf.
    Tries the axis of widest centre spread first, then the other one; a split
    counts only if both sides end up with fewer boxes than the node.
    """
    m = members.shape[0]
    if m > leaf_size and depth < max_depth:
        widest = widest_axis(lo, hi, members)
        for axis in (widest, 1 - widest):
            value = median_split_value(lo, hi, members, axis)
            left, right = split_sides(lo, hi, members, axis, value)
            if left.shape[0] < m and right.shape[0] < m:
                return axis, value, left, right
    return -1, 0.0, members, members


@njit(cache=True)
def split_region(region, axis, value):
    """Left and right halves of region (x0, y0, x1, y1), cut at `value` on `axis`."""
    x0, y0, x1, y1 = region
    if axis == 0:
        return (x0, y0, value, y1), (value, y0, x1, y1)
    return (x0, y0, x1, value), (x0, value, x1, y1)


@njit(cache=True)
def leaf_pairs(lo, hi, members, region, pairs, count):
    """Append the overlapping pairs of one leaf whose intersection's lower-left
    corner lies in the leaf's region [x0, x1) x [y0, y1)."""
    x0, y0, x1, y1 = region
    for a in range(members.shape[0]):
        i = members[a]
        for b in range(a + 1, members.shape[0]):
            j = members[b]
            if boxes_overlap(lo, hi, i, j):
                corner_x = max(lo[i, 0], lo[j, 0])
                corner_y = max(lo[i, 1], lo[j, 1])
                if x0 <= corner_x < x1 and y0 <= corner_y < y1:
                    pairs, count = push_pair(pairs, count, i, j)
    return pairs, count


@njit(cache=True)
def kdtree_pairs(lo, hi, leaf_size, max_depth):
    """Build the k-d tree and collect overlapping pairs from its leaves.

    lo, hi: (n, 2). Returns (pairs (k, 2) intp with i < j, node count, tree depth).
    """
    n = lo.shape[0]
    pairs, count = new_pair_buffer(n), 0
    n_nodes, tree_depth = 0, 0
    whole_plane = (-np.inf, -np.inf, np.inf, np.inf)
    stack = [(np.arange(n), 0, whole_plane)]
    while len(stack) > 0:
        members, depth, region = stack.pop()
        n_nodes += 1
        tree_depth = max(tree_depth, depth)
        axis, value, left, right = split_node(lo, hi, members, depth, leaf_size, max_depth)
        if axis < 0:
            pairs, count = leaf_pairs(lo, hi, members, region, pairs, count)
            continue
        left_region, right_region = split_region(region, axis, value)
        stack.append((right, depth + 1, right_region))
        stack.append((left, depth + 1, left_region))
    return pairs[:count], n_nodes, tree_depth


@njit(cache=True)
def build_kdtree(lo, hi, leaf_size, max_depth):
    """Build the k-d tree (the same splits as kdtree_pairs) into flat arrays.

    lo, hi: (n, 2), n >= 1. Returns, for m nodes numbered depth-first with
    the two children of a node next to each other:
    node_axis (m,): the split axis, -1 for a leaf;
    node_value (m,): the split value (left: coordinate < value, right: >=);
    node_left (m,): the left child (the right child is left + 1), -1 for a leaf;
    node_first, node_count (m,): a leaf's boxes are
    leaf_boxes[node_first:node_first + node_count];
    leaf_boxes (total,): every leaf's boxes, one run per leaf; a box that
    straddles a split appears in several runs.
    Straddlers make the sizes unknown in advance, so the arrays grow as needed.
    """
    n = lo.shape[0]
    capacity = 2 * n + 1
    node_axis = np.empty(capacity, np.intp)
    node_value = np.empty(capacity)
    node_left = np.empty(capacity, np.intp)
    node_first = np.empty(capacity, np.intp)
    node_count = np.empty(capacity, np.intp)
    leaf_boxes = np.empty(capacity, np.intp)
    n_nodes, n_leaf_boxes = 1, 0
    stack = [(0, np.arange(n), 0)]
    while len(stack) > 0:
        node, members, depth = stack.pop()
        axis, value, left, right = split_node(lo, hi, members, depth, leaf_size, max_depth)
        node_axis[node], node_value[node] = axis, value
        node_left[node], node_first[node], node_count[node] = -1, n_leaf_boxes, 0
        if axis < 0:
            m = members.shape[0]
            leaf_boxes = grown(leaf_boxes, n_leaf_boxes + m)
            leaf_boxes[n_leaf_boxes:n_leaf_boxes + m] = members
            node_count[node] = m
            n_leaf_boxes += m
            continue
        child = n_nodes
        n_nodes += 2
        node_axis = grown(node_axis, n_nodes)
        node_value = grown(node_value, n_nodes)
        node_left = grown(node_left, n_nodes)
        node_first = grown(node_first, n_nodes)
        node_count = grown(node_count, n_nodes)
        node_left[node] = child
        stack.append((child + 1, right, depth + 1))
        stack.append((child, left, depth + 1))
    return (node_axis[:n_nodes], node_value[:n_nodes], node_left[:n_nodes],
            node_first[:n_nodes], node_count[:n_nodes], leaf_boxes[:n_leaf_boxes])


@njit(cache=True)
def kdtree_query(lo, hi, node_axis, node_value, node_left, node_first, node_count, leaf_boxes,
                 qx0, qy0, qx1, qy1):
    """Boxes overlapping the query box [qx0, qx1] x [qy0, qy1] (tree from build_kdtree).

    The query box meets the left region (coordinate < value) if its min is
    < value, and the right one if its max is >= value: the same rule that
    files boxes, so every box overlapping the query sits in a leaf it reaches.
    Returns (found (k,) intp with repeats, nodes visited, boxes tested).
    """
    found, count = np.empty(16, np.intp), 0
    visited = tested = 0
    stack = [0]
    while len(stack) > 0:
        node = stack.pop()
        visited += 1
        axis = node_axis[node]
        if axis < 0:
            first, end = node_first[node], node_first[node] + node_count[node]
            tested += end - first
            found, count = overlapping_in_run(lo, hi, leaf_boxes, first, end, qx0, qy0, qx1, qy1, found, count)
            continue
        q_min, q_max = (qx0, qx1) if axis == 0 else (qy0, qy1)
        if q_max >= node_value[node]:
            stack.append(node_left[node] + 1)
        if q_min < node_value[node]:
            stack.append(node_left[node])
    return found[:count], visited, tested


@njit(cache=True)
def kdtree_raycast(lo, hi, node_axis, node_value, node_left, node_first, node_count, leaf_boxes,
                   x0, y0, x1, y1, ox, oy, ux, uy, max_distance):
    """Boxes the ray meets (tree from build_kdtree; x0, y0, x1, y1: the boxes'
    bounding box, the root's region).

    A node is entered only if the ray reaches its region (closed, so a ray
    along a split line goes both ways) within max_distance; of two children
    the nearer is searched first. Returns found (k,) intp with repeats,
    t_enter (k,) float64, nodes visited (regions tested) and boxes tested.
    """
    (found, t_enter), count = new_hit_buffers(), 0
    visited, tested = 1, 0
    stack = [(0, (x0, y0, x1, y1))]
    if ray_box_entry(ox, oy, ux, uy, max_distance, x0, y0, x1, y1) == np.inf:
        stack.pop()  # the ray misses the bounding box of all the boxes
    while len(stack) > 0:
        node, region = stack.pop()
        axis = node_axis[node]
        if axis < 0:
            tested += node_count[node]
            found, t_enter, count = hits_in_run(lo, hi, leaf_boxes, node_first[node],
                                                node_first[node] + node_count[node], ox, oy, ux, uy, max_distance,
                                                found, t_enter, count)
            continue
        # A split value may lie outside the node's region (the median centre
        # of boxes that straddle an earlier split); cut at the nearest side then.
        value = min(max(node_value[node], region[axis]), region[axis + 2])
        left_region, right_region = split_region(region, axis, value)
        t_left = ray_box_entry(ox, oy, ux, uy, max_distance, *left_region)
        t_right = ray_box_entry(ox, oy, ux, uy, max_distance, *right_region)
        visited += 2
        # The nearer child is searched first.
        left = node_left[node]
        regions = (left_region, right_region)
        far, far_reached, near, near_reached = farther_then_nearer(t_left, t_right)
        if far_reached:
            stack.append((left + far, regions[far]))
        if near_reached:
            stack.append((left + near, regions[near]))
    return found[:count], t_enter[:count], visited, tested


class KDTree(BroadPhase):
    """k-d tree broad phase, rebuilt every frame."""

    name = "kdtree"
    OPTIONS = ("leaf_size", "max_depth")
    EMPTY_STATS = {"nodes": 0, "depth": 0}

    def __init__(self, leaf_size=2, max_depth=32):
        super().__init__()
        self.leaf_size = check_int_option("leaf_size", leaf_size, 1)
        self.max_depth = check_int_option("max_depth", max_depth, 0)

    def _find(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        pairs, n_nodes, depth = kdtree_pairs(lo, hi, self.leaf_size, self.max_depth)
        self.stats.update(nodes=n_nodes, depth=depth)
        return pairs

    def _query(self, lo, hi, qx0, qy0, qx1, qy1):
        tree = build_kdtree(lo, hi, self.leaf_size, self.max_depth)
        return kdtree_query(lo, hi, *tree, qx0, qy0, qx1, qy1)

    def _raycast(self, lo, hi, ox, oy, ux, uy, max_distance):
        tree = build_kdtree(lo, hi, self.leaf_size, self.max_depth)
        (x0, y0), (x1, y1) = bounding_box(lo, hi)
        return kdtree_raycast(lo, hi, *tree, x0, y0, x1, y1, ox, oy, ux, uy, max_distance)

    def describe(self, lo, hi) -> dict:
        """Splits as (axis, value, node_lo, node_hi, depth) in build order, the
        leaves' box indices, and the pairs. Node regions are clipped to the
        boxes' bounding box so they can be drawn."""
        lo, hi = check_boxes(lo, hi)
        bounds = bounding_box(lo, hi) if len(lo) else (np.zeros(2), np.zeros(2))
        splits, leaves = [], []
        stack = [(np.arange(len(lo)), 0, *bounds)]
        while stack:
            members, depth, node_lo, node_hi = stack.pop()
            axis, value, left, right = split_node(lo, hi, members, depth,
                                                  self.leaf_size, self.max_depth)
            if axis < 0:
                leaves.append(members)
                continue
            splits.append((axis, value, node_lo, node_hi, depth))
            left_hi, right_lo = node_hi.copy(), node_lo.copy()
            left_hi[axis] = right_lo[axis] = np.clip(value, node_lo[axis], node_hi[axis])
            stack.append((right, depth + 1, right_lo, node_hi))
            stack.append((left, depth + 1, node_lo, left_hi))
        return {"splits": splits, "leaves": leaves, "pairs": self.pairs(lo, hi)}
