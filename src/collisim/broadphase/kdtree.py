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
"""

import numpy as np
from numba import njit

from ._common import (BroadPhase, bounding_box, boxes_overlap, check_boxes, check_int_option,
                      new_pair_buffer, push_pair, widest_axis)


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
