"""Convex polygons against polygons, circles, thin segments and half-planes (the box walls).

Every function takes WORLD-frame vertices (k, 2), counter-clockwise (geometry/polygon.py:
world_vertices), and returns a manifold, the tuple

    (nx, ny, count, depth0, px0, py0, depth1, px1, py1)

- (nx, ny): unit normal from the first shape towards the second; moving the second shape by
  depth0 along it separates the two (they are left touching).
- count: 0, 1 or 2 contact points; unused slots are 0.0. Touching (depth exactly 0) counts.
- each point (px, py) has its own depth (>= 0); point 0 is the deepest, and depth0 is the
  penetration depth of the pair (the length of the shortest move that separates them).
- apart: count 0 and depth0 = -(the distance between the shapes); (nx, ny) then points from
  the first shape's closest point to the second's, so callers can tell near misses.

Where the points are: midway between the two surfaces, as in Box2D v3. Each contact is a
pair of surface points, s_a on the first shape and s_b on the second, with s_a - s_b =
depth·n; the reported point is their midpoint, so point + (depth/2)·n lies on the first
shape's surface and point - (depth/2)·n on the second's, whichever shape is the reference
(swapping the pair gives the same points, unless a near tie picks the other reference
face: see FACE_TOLERANCE). For polygons, clipping finds the
pairs as Box2D does (b2CollidePolygons, b2ClipPolygons): the reference face is the face of
least penetration, the incident edge the other polygon's edge facing it, and the incident
edge's ends, cut to the reference face's width, are the incident surface points.

The helpers handed polygons are kernels (compiling.kernel) called, not inlined: inlined into
their callers (numba's inline="always"), each caller typed and compiled them again.

Separations are computed as cross products with the unnormalised edge (e × d) and divided by
|e| once, so a vertex lying exactly on another polygon's edge line gives exactly 0 (touching).
"""
import math

import numpy as np

from ..core.compiling import compiled, kernel
from ..core.geometry.box import wall_geometry
from ..core.geometry.segment import closest_on_segment
from ..core.geometry.vector import length

# A face of b is only preferred over a's face when it is this much (relative to the shorter of
# the two faces) less deep: near ties then keep the same reference face from step to step,
# instead of flipping on round-off (Box2D v2's k_tol; v3 just prefers a on exact ties). It
# changes a depth by at most this much, far below what a test at 1e-9 would see.
FACE_TOLERANCE = 1e-10


@kernel
def _next(i, k):
    return i + 1 if i + 1 < k else 0


@kernel
def _behind(x, y, ox, oy, ex, ey):
    """How far p = (x, y) lies behind the line through o along e, times |e|: the cross product
    e × (p − o), positive on the left of e — inside, for a counter-clockwise polygon's edge."""
    return ex * (y - oy) - ey * (x - ox)


@kernel
def _max_separation(a, b):
    """The separating-axis test over a's edge normals: (separation, edge, deepest) — the
    largest over a's edges of how far b's deepest vertex lies in front of the edge (negative:
    behind it, overlapping), that edge, and the index of b's deepest vertex."""
    ka, kb = a.shape[0], b.shape[0]
    best, edge, deepest = -np.inf, 0, 0
    for i in range(ka):
        j = _next(i, ka)
        ex, ey = a[j, 0] - a[i, 0], a[j, 1] - a[i, 1]
        most, index = -np.inf, 0
        for m in range(kb):
            d = _behind(b[m, 0], b[m, 1], a[i, 0], a[i, 1], ex, ey)
            if d > most:
                most, index = d, m
        separation = -most / length(ex, ey)
        if separation > best:
            best, edge, deepest = separation, i, index
    return best, edge, deepest


@kernel
def _separated(a, a0, a1, b, b0, b1):
    """Is there an edge of polygon a[a0:a1] with every vertex of b[b0:b1] strictly in front of it?
    Rows of whole arrays rather than slices: a slice costs numba a reference count, which for
    a pair in a pile is twice the test."""
    for i in range(a0, a1):
        j = i + 1 if i + 1 < a1 else a0
        ex, ey = a[j, 0] - a[i, 0], a[j, 1] - a[i, 1]
        front = True
        for m in range(b0, b1):
            if _behind(b[m, 0], b[m, 1], a[i, 0], a[i, 1], ex, ey) >= 0.0:
                front = False
                break
        if front:
            return True
    return False


@kernel
def polygons_touch(a, b):
    """Do convex polygons a (ka, 2) and b (kb, 2) overlap or touch? The separating-axis test,
    stopping at the first edge that separates them. A thin segment is a 2-vertex polygon."""
    ka, kb = a.shape[0], b.shape[0]
    return not _separated(a, 0, ka, b, 0, kb) and not _separated(b, 0, kb, a, 0, ka)


@kernel
def placed_polygons_touch(vertices, start, i, j):
    """polygons_touch of polygons i and j among placed vertices (V, 2), polygon k's in
    vertices[start[k]:start[k + 1]], without slicing them out."""
    a0, a1, b0, b1 = start[i], start[i + 1], start[j], start[j + 1]
    return (not _separated(vertices, a0, a1, vertices, b0, b1)
            and not _separated(vertices, b0, b1, vertices, a0, a1))


@kernel
def _closest_points(a, b):
    """(distance, ax, ay, bx, by): the closest points of two disjoint convex polygons. One of
    them is always a vertex, the other on an edge of the other polygon, so every
    vertex–edge pair both ways is tried."""
    best, ax, ay, bx, by = np.inf, 0.0, 0.0, 0.0, 0.0
    for swap in range(2):
        p, q = (a, b) if swap == 0 else (b, a)
        for i in range(p.shape[0]):
            for e in range(q.shape[0]):
                f = _next(e, q.shape[0])
                qx, qy, _ = closest_on_segment(p[i, 0], p[i, 1], q[e, 0], q[e, 1], q[f, 0], q[f, 1])
                d2 = (p[i, 0] - qx) ** 2 + (p[i, 1] - qy) ** 2
                if d2 < best:
                    best = d2
                    if swap == 0:
                        ax, ay, bx, by = p[i, 0], p[i, 1], qx, qy
                    else:
                        ax, ay, bx, by = qx, qy, p[i, 0], p[i, 1]
    return math.sqrt(best), ax, ay, bx, by


@kernel
def _apart(ax, ay, bx, by, distance):
    """The manifold of two shapes `distance` apart, closest points a and b."""
    nx, ny = (bx - ax) / distance, (by - ay) / distance
    return nx, ny, 0, -distance, 0.0, 0.0, 0.0, 0.0, 0.0


@kernel
def _corner(ax, ay, bx, by, distance):
    """The speculative manifold of two shapes `distance` apart whose closest points a and b are
    corners: one point, midway between them, along the line that joins them."""
    nx, ny = (bx - ax) / distance, (by - ay) / distance
    return nx, ny, 1, -distance, 0.5 * (ax + bx), 0.5 * (ay + by), 0.0, 0.0, 0.0


@kernel
def _incident_edge(p, deepest, nx, ny):
    """Of the two edges of polygon p at its deepest vertex, the start of the one whose outward
    normal points most against (nx, ny): the face that meets the reference face."""
    before = deepest - 1 if deepest > 0 else p.shape[0] - 1
    return before if _facing(p, before, nx, ny) < _facing(p, deepest, nx, ny) else deepest


@kernel
def _facing(p, i, nx, ny):
    """The cosine between edge i's outward normal and (nx, ny)."""
    j = _next(i, p.shape[0])
    ex, ey = p[j, 0] - p[i, 0], p[j, 1] - p[i, 1]
    return (ey * nx - ex * ny) / length(ex, ey)


@kernel
def _clip_behind(px, py, qx, qy, tx, ty, ox, oy):
    """Sutherland–Hodgman against one plane: the part of segment p–q with t·(x − o) <= 0.
    Returns (kept, px, py, qx, qy); kept is False when nothing is left."""
    dp = tx * (px - ox) + ty * (py - oy)
    dq = tx * (qx - ox) + ty * (qy - oy)
    if dp > 0.0 and dq > 0.0:
        return False, px, py, qx, qy
    if dp > 0.0:
        s = dp / (dp - dq)
        px, py = px + s * (qx - px), py + s * (qy - py)
    elif dq > 0.0:
        s = dq / (dq - dp)
        qx, qy = qx + s * (px - qx), qy + s * (py - qy)
    return True, px, py, qx, qy


@kernel
def _clip_to_face(ref, face, inc, edge):
    """The incident edge of polygon `inc` clipped to the width of reference face `face` of
    polygon `ref`: (kept, px, py, depth_p, qx, qy, depth_q), depths measured behind the face."""
    r0, r1 = face, _next(face, ref.shape[0])
    ox, oy = ref[r0, 0], ref[r0, 1]
    ex, ey = ref[r1, 0] - ox, ref[r1, 1] - oy
    size = length(ex, ey)
    tx, ty = ex / size, ey / size
    i, j = edge, _next(edge, inc.shape[0])
    px, py, qx, qy = inc[i, 0], inc[i, 1], inc[j, 0], inc[j, 1]
    kept, px, py, qx, qy = _clip_behind(px, py, qx, qy, tx, ty, ref[r1, 0], ref[r1, 1])
    if kept:
        kept, px, py, qx, qy = _clip_behind(px, py, qx, qy, -tx, -ty, ox, oy)
    depth_p = _behind(px, py, ox, oy, ex, ey) / size
    depth_q = _behind(qx, qy, ox, oy, ex, ey) / size
    return kept, px, py, depth_p, qx, qy, depth_q


@kernel
def _two_points(nx, ny, px, py, depth_p, qx, qy, depth_q, reach):
    """A manifold from two candidate points: those at depth >= -reach (0 for shapes that touch;
    a speculative manifold's margin), deepest first (one when both are the same point, as at a corner
    touching a face's end)."""
    if depth_q > depth_p:
        px, py, depth_p, qx, qy, depth_q = qx, qy, depth_q, px, py, depth_p
    if depth_q + reach < 0.0 or (qx == px and qy == py):
        return nx, ny, 1, depth_p, px, py, 0.0, 0.0, 0.0
    return nx, ny, 2, depth_p, px, py, depth_q, qx, qy


@kernel
def polygon_polygon(a, b, beyond=np.inf, reach=0.0):
    """The manifold of convex polygons a (ka, 2) and b (kb, 2), world frame, counter-clockwise
    (see the module docstring). The reference face is a's unless one of b's is less deep by
    more than FACE_TOLERANCE. Polygons an axis separates by `beyond` (> 0) or more are not
    measured further (their distance is at least that, and finding it costs every vertex against
    every edge): count 0 and depth0 = -(that separation). Of two points on the incident edge,
    the shallower is kept if no more than `reach` apart (a tilted face resting on another: the
    raised end's speculative point)."""
    return _polygons_manifold(a, b, beyond, False, reach)


@kernel
def speculative_polygons(a, b, margin):
    """polygon_polygon, except for polygons apart by less than `margin` (> 0) whose closest
    features are a face and a vertex (the vertex lies in front of the face, not beyond its
    ends): their manifold taken where they are — the face's normal, the incident edge clipped to
    the face, each point with its depth (-gap for the nearest; the other kept if it is within
    the margin too), midway between the surfaces. The gap is then the separating-axis test's own
    separation (a vertex over a face is exactly that far), so neither the closest points (every
    vertex against every edge) nor a second test is needed. Closer than `margin` otherwise
    (corner against corner): one point, midway between the closest points, depth -distance.
    Touching or overlapping: polygon_polygon's manifold with reach = margin (a tilted face's
    raised end is kept up to the margin apart). Farther: as polygon_polygon."""
    return _polygons_manifold(a, b, margin, True, margin)


@kernel
def _over_face(ref, face, p):
    """Does point p lie in front of reference face `face` of polygon ref, between its ends?"""
    r1 = _next(face, ref.shape[0])
    ex, ey = ref[r1, 0] - ref[face, 0], ref[r1, 1] - ref[face, 1]
    along = ex * (p[0] - ref[face, 0]) + ey * (p[1] - ref[face, 1])
    return 0.0 <= along <= ex * ex + ey * ey


@kernel
def _polygons_manifold(a, b, beyond, speculative, reach):
    separation_a, face_a, deepest_b = _max_separation(a, b)
    separation_b, face_b, deepest_a = _max_separation(b, a)
    separation = max(separation_a, separation_b)
    if separation >= beyond > 0.0:
        return 1.0, 0.0, 0, -separation, 0.0, 0.0, 0.0, 0.0, 0.0
    tolerance = FACE_TOLERANCE * min(_edge_length(a, face_a), _edge_length(b, face_b))
    flip = separation_b > separation_a + tolerance
    ref, face, inc, deepest = (b, face_b, a, deepest_a) if flip else (a, face_a, b, deepest_b)
    gap = 0.0
    if separation > 0.0:
        if (speculative and separation < beyond and (separation_b if flip else separation_a) == separation
                and _over_face(ref, face, inc[deepest])):
            gap = separation   # a vertex in front of a face: the gap is the separation
        else:
            distance, ax, ay, bx, by = _closest_points(a, b)
            if distance > 0.0:
                if speculative and distance < beyond:   # corner against corner: one point
                    return _corner(ax, ay, bx, by, distance)
                return _apart(ax, ay, bx, by, distance)
            # an axis separates them by a rounding error while a vertex lies on the other: they
            # touch (no normal joins two closest points that coincide), so the faces' manifold
    r1 = _next(face, ref.shape[0])
    ex, ey = ref[r1, 0] - ref[face, 0], ref[r1, 1] - ref[face, 1]
    size = length(ex, ey)
    nx, ny = ey / size, -ex / size              # the reference face's outward normal
    edge = _incident_edge(inc, deepest, nx, ny)
    kept, px, py, depth_p, qx, qy, depth_q = _clip_to_face(ref, face, inc, edge)
    if not kept or max(depth_p, depth_q) + gap < 0.0:
        # Only round-off can cut the deepest vertex off the face (the closest point of the
        # Minkowski difference lies on the face): then it is the one contact.
        px, py, depth_p = inc[deepest, 0], inc[deepest, 1], -(separation_b if flip else separation_a)
        qx, qy, depth_q = px, py, depth_p
    # Midway: half the depth out along the reference normal from the incident surface.
    px, py = px + 0.5 * depth_p * nx, py + 0.5 * depth_p * ny
    qx, qy = qx + 0.5 * depth_q * nx, qy + 0.5 * depth_q * ny
    if flip:
        nx, ny = -nx, -ny                           # the normal runs from a to b
    # apart, both points within the margin count, and touching, the shallower within `reach`
    # (speculative points act only if the step would close their gap, as in Box2D, which keeps
    # every clipped point up to its speculative distance; the walls' manifolds keep theirs so too)
    return _two_points(nx, ny, px, py, depth_p, qx, qy, depth_q, beyond if gap > 0.0 else reach)


@kernel
def _edge_length(p, i):
    j = _next(i, p.shape[0])
    return length(p[j, 0] - p[i, 0], p[j, 1] - p[i, 1])


@kernel
def _nearest_feature(a, cx, cy):
    """Where the point c meets convex polygon a: (signed distance, nx, ny) — the distance
    from a's surface (negative inside) and the outward unit normal there.
    The face c lies farthest in front of is next to c's closest feature (Ericson 5.1), so
    one face and its two ends settle it."""
    k = a.shape[0]
    best, face = -np.inf, 0
    for i in range(k):
        j = _next(i, k)
        ex, ey = a[j, 0] - a[i, 0], a[j, 1] - a[i, 1]
        separation = -_behind(cx, cy, a[i, 0], a[i, 1], ex, ey) / length(ex, ey)
        if separation > best:
            best, face = separation, i
    j = _next(face, k)
    ex, ey = a[j, 0] - a[face, 0], a[j, 1] - a[face, 1]
    size = length(ex, ey)
    nx, ny = ey / size, -ex / size
    qx, qy, u = closest_on_segment(cx, cy, a[face, 0], a[face, 1], a[j, 0], a[j, 1])
    if best > 0.0 and (u == 0.0 or u == 1.0):      # outside, beyond an end: a vertex region
        distance = length(cx - qx, cy - qy)
        return distance, (cx - qx) / distance, (cy - qy) / distance
    return best, nx, ny


@kernel
def polygon_circle_touch(a, cx, cy, r):
    """Does convex polygon a (k, 2) overlap or touch the circle (cx, cy, r)?"""
    return _nearest_feature(a, cx, cy)[0] <= r


@kernel
def polygon_circle(a, cx, cy, r):
    """The manifold of convex polygon a (k, 2) and the circle (cx, cy, r): normal from the
    polygon towards the circle (along the vertex-to-centre line in a vertex region, the face
    normal otherwise, also when the centre is inside); one point, midway between the
    polygon's surface point (the nearest to the centre, or the foot on the nearest face) and
    the circle's deepest point c - r·n."""
    distance, nx, ny = _nearest_feature(a, cx, cy)
    depth = r - distance
    if depth < 0.0:
        return nx, ny, 0, depth, 0.0, 0.0, 0.0, 0.0, 0.0
    reach = 0.5 * (distance + r)
    return nx, ny, 1, depth, cx - reach * nx, cy - reach * ny, 0.0, 0.0, 0.0


@compiled(error_model="numpy")
def polygon_segment(a, x0, y0, x1, y1, reach=0.0):
    """The manifold of convex polygon a (k, 2) and the thin segment (x0, y0)-(x1, y1): normal
    from the polygon towards the segment, up to two points (the second kept if no more than
    `reach` apart, as polygon_polygon's). The segment is the degenerate two-sided polygon
    [(x0, y0), (x1, y1)], whose two edges face opposite ways; a segment of no length is a point
    (a circle of radius 0)."""
    if x0 == x1 and y0 == y1:
        return polygon_circle(a, x0, y0, 0.0)
    segment = np.empty((2, 2))
    segment[0, 0], segment[0, 1], segment[1, 0], segment[1, 1] = x0, y0, x1, y1
    return polygon_polygon(a, segment, np.inf, reach)


@kernel
def polygon_halfplane(a, nx, ny, offset):
    """The manifold of convex polygon a (k, 2) and the solid half-plane {p : n·p <= offset},
    where (nx, ny) is the unit normal pointing out of the solid (into the free side). The
    contact normal, polygon to half-plane, is -n; the points come from the (up to two)
    deepest vertices in the solid, each `offset - n·v` deep, and lie midway between the vertex
    and the boundary line. Box walls: box_wall_halfplane."""
    first, second, deepest, runner_up = 0, 0, -np.inf, -np.inf
    for i in range(a.shape[0]):
        depth = offset - (nx * a[i, 0] + ny * a[i, 1])
        if depth > deepest:
            first, second, deepest, runner_up = i, first, depth, deepest
        elif depth > runner_up:
            second, runner_up = i, depth
    if deepest < 0.0:
        return -nx, -ny, 0, deepest, 0.0, 0.0, 0.0, 0.0, 0.0
    px, py = a[first, 0] + 0.5 * deepest * nx, a[first, 1] + 0.5 * deepest * ny
    if runner_up < 0.0:
        return -nx, -ny, 1, deepest, px, py, 0.0, 0.0, 0.0
    qx, qy = a[second, 0] + 0.5 * runner_up * nx, a[second, 1] + 0.5 * runner_up * ny
    return -nx, -ny, 2, deepest, px, py, runner_up, qx, qy


@kernel
def box_wall_halfplane(box, wall):
    """The solid beyond one wall of the box as polygon_halfplane's (nx, ny, offset).
    box: (4,) xmin, ymin, xmax, ymax; wall: 0 left, 1 right, 2 bottom, 3 top (kinds.WALL_SIDES).
    n points into the box, so the solid is everything outside that wall."""
    axis, bound, inward = wall_geometry(box, wall, 0.0)
    if axis == 0:
        return inward, 0.0, inward * bound
    return 0.0, inward, inward * bound
