"""How close two shapes come while one slides past the other: the least distance over a step in
which the second shape moves by a straight displacement d relative to the first.

A speculative manifold (manifold.py) is taken where the step starts: its normal joins the
closest features there. Along that normal a corner sliding past a corner seems to close faster
than its gap, though the two never meet — a ghost collision. The sweep asks the question the
normal cannot answer: do the shapes come together at all within the step?

For two disjoint convex polygons the closest points are a vertex of one and a point on an edge
of the other. So the least distance over the sweep is the least, over every vertex and every
edge of the other shape, of the distance between the vertex's path (a segment) and that edge;
it is 0 exactly when some vertex path crosses an edge, which it must before the shapes overlap.
A circle is its centre with its radius: its centre's path against the polygon's edges, less the
radius.
"""
import math

from ..core.compiling import kernel

from ..core.geometry.segment import closest_on_segment
from ..core.geometry.vector import length


@kernel
def _point_segment(px, py, x0, y0, x1, y1):
    qx, qy, _ = closest_on_segment(px, py, x0, y0, x1, y1)
    return length(px - qx, py - qy)


@kernel
def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


@kernel
def segments_distance(ax, ay, bx, by, cx, cy, dx, dy):
    """The distance between segments a-b and c-d: 0 if they cross, else the least of each end's
    distance to the other segment."""
    d1 = _cross(bx - ax, by - ay, cx - ax, cy - ay)
    d2 = _cross(bx - ax, by - ay, dx - ax, dy - ay)
    d3 = _cross(dx - cx, dy - cy, ax - cx, ay - cy)
    d4 = _cross(dx - cx, dy - cy, bx - cx, by - cy)
    if ((d1 > 0.0 > d2) or (d1 < 0.0 < d2)) and ((d3 > 0.0 > d4) or (d3 < 0.0 < d4)):
        return 0.0
    return min(_point_segment(ax, ay, cx, cy, dx, dy), _point_segment(bx, by, cx, cy, dx, dy),
               _point_segment(cx, cy, ax, ay, bx, by), _point_segment(dx, dy, ax, ay, bx, by))


@kernel
def _paths_to_edges(p, q, sx, sy, best):
    """The least distance between the path of each vertex of p, from v to v + s, and each edge of
    q (both (k, 2), q counter-clockwise), or best if that is less."""
    kq = q.shape[0]
    for m in range(p.shape[0]):
        x, y = p[m, 0], p[m, 1]
        for e in range(kq):
            f = e + 1 if e + 1 < kq else 0
            best = min(best, segments_distance(x, y, x + sx, y + sy, q[e, 0], q[e, 1], q[f, 0], q[f, 1]))
            if best == 0.0:
                return 0.0
    return best


@kernel
def swept_polygons(a, b, dx, dy):
    """The least distance between convex polygons a and b (k, 2) (disjoint at the start) while b
    moves by (dx, dy) relative to a."""
    best = _paths_to_edges(b, a, dx, dy, math.inf)
    return _paths_to_edges(a, b, -dx, -dy, best)   # a's vertices seen from b move by -d


@kernel
def swept_polygon_circle(a, cx, cy, r, dx, dy):
    """The least gap between convex polygon a (k, 2) and the circle (cx, cy, r) (apart at the
    start) while the circle moves by (dx, dy) relative to a."""
    k, best = a.shape[0], math.inf
    for e in range(k):
        f = e + 1 if e + 1 < k else 0
        best = min(best, segments_distance(cx, cy, cx + dx, cy + dy, a[e, 0], a[e, 1], a[f, 0], a[f, 1]))
    return best - r


@kernel
def swept_circles(ox, oy, dx, dy, rsum):
    """The least gap between two circles whose centres are (ox, oy) apart (second less first) at
    the start while the second moves by (dx, dy) relative to the first; rsum their radii's sum."""
    dd = dx * dx + dy * dy
    t = 0.0 if dd == 0.0 else min(max(-(ox * dx + oy * dy) / dd, 0.0), 1.0)
    return length(ox + t * dx, oy + t * dy) - rsum
