"""k-d tree: split space in two at the median, again and again.

Start with one region holding every box. Split it with a line through the
median of the box centres, so that half the boxes lie on each side. A box
that straddles the line goes to *both* sides: it could touch boxes on either.
Repeat on each side on the opposite axis, as the video does: x at the root,
y one level down, x the next, ... (the axis is the depth's parity). Stop when
a region is a leaf, then test the boxes inside each leaf against each other.

A region becomes a leaf when

* it holds at most ``leaf_size`` boxes, or
* it sits ``max_depth`` splits deep, or
* no split helps: if one side would still hold every box, splitting removes
  nothing (the video's example: two overlapping particles straddle any line
  between them, so both sides would keep both). We then try the other axis
  (beyond the video: boxes lined up across the depth's axis, all straddling
  its median, would otherwise leave one crowded leaf), and if that fails too
  the region stays a leaf. Requiring both sides to shrink also guarantees
  that the recursion ends. The children still take their own depth's axis.

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

:func:`grow_kdtree` builds the tree into flat arrays (allocated once per
build, nothing per node); pairs, box queries and ray casts all read them.
A query box goes down the tree the way a box is filed into it: left if its min is < the split value, right if its
max is >= it. A ray goes into the children whose region it reaches within
max_distance, nearer child first.
"""

import numpy as np

from ..core.arrays import grown
from ..core.compiling import compiled, kernel
from ._common import (BroadPhase, bounding_box, boxes_overlap, check_boxes, check_int_option, copy_row, gathered_boxes,
                      new_pair_buffer, overlapping_in_run, push_pair, row_centre, select_smallest)
from ._rays import farther_then_nearer, hits_in_run, new_hit_buffers, ray_box_entry


@kernel
def median_split_value(rows, axis, keys):
    """Split line on `axis` with the lower half of the centres of box rows (m, 4), m >= 2,
    (gathered_boxes) on its left: halfway between the two middle centres. keys: (>= m,)
    scratch. select_smallest puts the upper middle one where a sort would, and the lower
    one is the largest before it (without sorting the rest)."""
    m = rows.shape[0]
    half = m // 2
    for k in range(m):
        keys[k] = row_centre(rows, k, axis)
    select_smallest(keys, m, half)
    lower = keys[0]
    for k in range(1, half):   # (a loop: keys[:half].max() compiles numba's reduction, 0.3 s)
        lower = max(lower, keys[k])
    return 0.5 * lower + 0.5 * keys[half]


@kernel
def side_counts(rows, axis, value):
    """How many box rows (m, 4) go left (min < value) and right (max >= value); straddlers
    go both ways."""
    left = right = 0
    for k in range(rows.shape[0]):
        left += rows[k, axis] < value
        right += rows[k, axis + 2] >= value
    return left, right


@kernel
def choose_split(rows, depth, leaf_size, max_depth, keys):
    """Decide whether and how to split a node.

    rows: (m, 4) the node's boxes (gathered_boxes); keys: scratch. Returns (axis, value,
    left count, right count), or axis -1 for a leaf. Tries the depth's axis first (x at
    even depths, y at odd ones: the video's alternation), then the other one; a split
    counts only if both sides end up with fewer boxes than the node.
    """
    m = rows.shape[0]
    if m > leaf_size and depth < max_depth:
        turn = depth % 2
        for axis in (turn, 1 - turn):
            value = median_split_value(rows, axis, keys)
            left, right = side_counts(rows, axis, value)
            if left < m and right < m:
                return axis, value, left, right
    return -1, 0.0, m, m


@kernel
def split_region(region, axis, value):
    """Left and right halves of region (x0, y0, x1, y1), cut at `value` on `axis`."""
    x0, y0, x1, y1 = region
    if axis == 0:
        return (x0, y0, value, y1), (value, y0, x1, y1)
    return (x0, y0, x1, value), (x0, value, x1, y1)


@compiled
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


@compiled
def kdtree_pairs(lo, hi, leaf_size, max_depth):
    """Build the k-d tree and collect overlapping pairs from its leaves.

    lo, hi: (n, 2). Returns (pairs (k, 2) intp with i < j, node count, tree depth).
    """
    node_axis, _, _, node_first, node_count, leaf_boxes, node_region, depth = grow_kdtree(
        lo, hi, leaf_size, max_depth)
    pairs, count = new_pair_buffer(lo.shape[0]), np.intp(0)
    for node in range(node_axis.shape[0]):
        if node_axis[node] < 0:
            first, end = node_first[node], node_first[node] + node_count[node]
            region = (node_region[node, 0], node_region[node, 1], node_region[node, 2], node_region[node, 3])
            pairs, count = leaf_pairs(lo, hi, leaf_boxes[first:end], region, pairs, count)
    return pairs[:count], node_axis.shape[0], depth


@compiled
def build_kdtree(lo, hi, leaf_size, max_depth):
    """The k-d tree in flat arrays (grow_kdtree's first six), for box queries and ray casts."""
    return grow_kdtree(lo, hi, leaf_size, max_depth)[:6]


@compiled
def grow_kdtree(lo, hi, leaf_size, max_depth):
    """Build the k-d tree into flat arrays.

    lo, hi: (n, 2). Returns, for m nodes numbered depth-first with the two
    children of a node next to each other:
    node_axis (m,): the split axis, -1 for a leaf;
    node_value (m,): the split value (left: coordinate < value, right: >=);
    node_left (m,): the left child (the right child is left + 1), -1 for a leaf;
    node_first, node_count (m,): a leaf's boxes are
    leaf_boxes[node_first:node_first + node_count];
    leaf_boxes (total,): every leaf's boxes, one run per leaf; a box that
    straddles a split appears in several runs;
    node_region (m, 4): x0, y0, x1, y1 of each node's region (the root's is the whole plane);
    and the tree's depth.

    A node's boxes are a run of one work array (the root's: 0 .. n - 1), their boxes gathered
    beside it (gathered_boxes). Splitting copies the right child's boxes to the top of the
    work array and compacts the left child's in place, both in the node's order; the left child is built first, and when a node is taken from
    the stack everything above its own run belongs to finished subtrees, so the top drops
    back. Nothing is allocated per node: the arrays start at 2n + 1 nodes and 2n boxes and
    double when straddlers need more.
    """
    n = lo.shape[0]
    keys = np.empty(n)
    work, work_rows = np.empty(2 * n, np.intp), np.empty((2 * n, 4))
    boxes = gathered_boxes(lo, hi)
    # element by element, here and below: an array or a tuple assigned to a slice or a row
    # compiles numba's shape check and its message (2.3 s of a first kd-tree's compiling)
    for k in range(n):
        work[k] = k
        copy_row(boxes, k, work_rows, k)
    capacity = 2 * n + 1
    node_axis = np.empty(capacity, np.intp)
    node_value = np.empty(capacity)
    node_left = np.empty(capacity, np.intp)
    node_first = np.empty(capacity, np.intp)
    node_count = np.empty(capacity, np.intp)
    node_region = np.empty((capacity, 4))
    node_region[0, 0], node_region[0, 1], node_region[0, 2], node_region[0, 3] = -np.inf, -np.inf, np.inf, np.inf
    leaf_boxes = np.empty(capacity, np.intp)
    n_nodes, n_leaf_boxes, tree_depth = 1, 0, 0
    # Pending nodes, left child on top: node, its run's start and length, depth, and the
    # work array's top when it is taken. At most one pending right child per level.
    stack = np.empty((max_depth + 2, 5), np.intp)
    stack[0, 0], stack[0, 1], stack[0, 2], stack[0, 3], stack[0, 4] = 0, 0, n, 0, n
    pending = 1
    while pending > 0:
        pending -= 1
        node, first, m, depth, top = stack[pending]
        tree_depth = max(tree_depth, depth)
        members = work[first:first + m]
        axis, value, n_left, n_right = choose_split(work_rows[first:first + m], depth, leaf_size, max_depth, keys)
        node_axis[node], node_value[node] = axis, value
        node_left[node], node_first[node], node_count[node] = -1, n_leaf_boxes, 0
        if axis < 0:
            leaf_boxes = grown(leaf_boxes, n_leaf_boxes + m)
            for k in range(m):
                leaf_boxes[n_leaf_boxes + k] = members[k]
            node_count[node] = m
            n_leaf_boxes += m
            continue
        child = n_nodes
        n_nodes += 2
        node_axis, node_value, node_left = grown(node_axis, n_nodes), grown(node_value, n_nodes), grown(node_left, n_nodes)
        node_first, node_count = grown(node_first, n_nodes), grown(node_count, n_nodes)
        node_region = grown(node_region, n_nodes)
        node_left[node] = child
        region = (node_region[node, 0], node_region[node, 1], node_region[node, 2], node_region[node, 3])
        below, above = split_region(region, axis, value)
        for c in range(4):
            node_region[child, c], node_region[child + 1, c] = below[c], above[c]
        work, work_rows = grown(work, top + n_right), grown(work_rows, top + n_right)
        right, left = top, first
        for k in range(first, first + m):  # right first: the left compaction overwrites the run
            if work_rows[k, axis + 2] >= value:
                work[right] = work[k]
                copy_row(work_rows, k, work_rows, right)
                right += 1
        for k in range(first, first + m):
            if work_rows[k, axis] < value:
                work[left] = work[k]
                copy_row(work_rows, k, work_rows, left)
                left += 1
        stack[pending, 0], stack[pending, 1], stack[pending, 2] = child + 1, top, n_right
        stack[pending, 3], stack[pending, 4] = depth + 1, top + n_right
        stack[pending + 1, 0], stack[pending + 1, 1], stack[pending + 1, 2] = child, first, n_left
        stack[pending + 1, 3], stack[pending + 1, 4] = depth + 1, top + n_right
        pending += 2
    return (node_axis[:n_nodes], node_value[:n_nodes], node_left[:n_nodes], node_first[:n_nodes],
            node_count[:n_nodes], leaf_boxes[:n_leaf_boxes], node_region[:n_nodes], tree_depth)


@compiled
def kdtree_query(lo, hi, node_axis, node_value, node_left, node_first, node_count, leaf_boxes,
                 qx0, qy0, qx1, qy1):
    """Boxes overlapping the query box [qx0, qx1] x [qy0, qy1] (tree from build_kdtree).

    The query box meets the left region (coordinate < value) if its min is
    < value, and the right one if its max is >= value: the same rule that
    files boxes, so every box overlapping the query sits in a leaf it reaches.
    Returns (found (k,) intp with repeats, nodes visited, boxes tested).
    """
    found, count = np.empty(16, np.intp), np.intp(0)
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


@compiled
def kdtree_raycast(lo, hi, node_axis, node_value, node_left, node_first, node_count, leaf_boxes,
                   x0, y0, x1, y1, ox, oy, ux, uy, max_distance):
    """Boxes the ray meets (tree from build_kdtree; x0, y0, x1, y1: the boxes'
    bounding box, the root's region).

    A node is entered only if the ray reaches its region (closed, so a ray
    along a split line goes both ways) within max_distance; of two children
    the nearer is searched first. Returns found (k,) intp with repeats,
    t_enter (k,) float64, nodes visited (regions tested) and boxes tested.
    """
    (found, t_enter), count = new_hit_buffers(), np.intp(0)
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
        node_axis, node_value, node_left, first, count, leaf_boxes = build_kdtree(
            lo, hi, self.leaf_size, self.max_depth)
        splits, leaves = [], []
        stack = [(0, 0, *bounds)]
        while stack:
            node, depth, node_lo, node_hi = stack.pop()
            axis, value, left = int(node_axis[node]), float(node_value[node]), int(node_left[node])
            if axis < 0:
                leaves.append(leaf_boxes[first[node]:first[node] + count[node]])
                continue
            splits.append((axis, value, node_lo, node_hi, depth))
            left_hi, right_lo = node_hi.copy(), node_lo.copy()
            left_hi[axis] = right_lo[axis] = np.clip(value, node_lo[axis], node_hi[axis])
            stack.append((left + 1, depth + 1, right_lo, node_hi))
            stack.append((left, depth + 1, node_lo, left_hi))
        return {"splits": splits, "leaves": leaves, "pairs": self.pairs(lo, hi)}
