"""Capsules against every shape and static: manifolds as narrowphase/polygons.py's tuple
(nx, ny, count, depth0, px0, py0, depth1, px1, py1), normal from the first shape to the second,
with speculative points up to `margin` apart (narrowphase/manifold.py's convention).

A capsule is its core, the segment between its cap centres, rounded by its radius r (Box2D v3
treats it as a two-vertex polygon with a radius; b2CollideCapsules, b2CollidePolygons). The
manifold of two rounded shapes is their cores' manifold grown (_grown): the same normal and
features, every depth deeper by both radii, each point moved to stay midway between the two
surfaces. This is exact for convex cores: the set of points within r of a convex set is convex,
its support in any direction is the core's plus r, so the separating axis of least overlap (or
the closest points, when apart) is the same, with the separation less by the radii. So:

- capsule–circle: the closest point of the core to the centre, then two circles;
- capsule–polygon: the cores as two polygons (polygons.speculative_polygons; a core is a thin
  two-sided segment, a polygon's radius 0), clipped to two points where faces lie along each other;
- capsule–capsule, capsule–segment (a capsule of radius 0): the cores' closest points, or,
  where the cores lie beside each other, the reference face and the other core clipped to it
  (Box2D v3's b2CollideCapsules);
- capsule–wall: each cap centre against the wall's half-plane (polygon_halfplane), up to two.

The capsule's radius is not passed to the kernels: it is its bounding radius less half its
core's length (capsule_radius), the World's radius to within a rounding of the core's placed
length, so every kernel of the vertex table (radii, vertices, start) handles capsules unchanged.
"""
import math

import numpy as np

from ..core.compiling import compiled, kernel
from ..core.geometry.capsule import ray_capsule
from ..core.geometry.segment import closest_on_segment
from ..core.kinds import CAPSULE, CIRCLE
from .polygons import box_wall_halfplane, polygon_halfplane, speculative_polygons
from .sweep import swept_polygon_circle, swept_polygons

NONE = (1.0, 0.0, 0, -np.inf, 0.0, 0.0, 0.0, 0.0, 0.0)
TOUCH = 1e-12   # of the coordinates' size: past any rounding of a core moved to touch another


@kernel
def capsule_radius(radii, vertices, start, i):
    """Capsule i's own radius: its bounding radius (half its core's length plus r) less half
    the length of its core placed in the world, vertices[start[i]:start[i] + 2]."""
    s = start[i]
    return radii[i] - 0.5 * math.hypot(vertices[s + 1, 0] - vertices[s, 0], vertices[s + 1, 1] - vertices[s, 1])


@compiled(error_model="numpy")
def _grown(m, ra, rb):
    """The manifold of two cores m, for the shapes they make rounded by ra (the first) and rb:
    deeper by ra + rb, each point moved to stay midway between the surfaces."""
    nx, ny, count, d0, px0, py0, d1, px1, py1 = m
    grow, shift = ra + rb, 0.5 * (ra - rb)
    return (nx, ny, count, d0 + grow, px0 + shift * nx, py0 + shift * ny, d1 + grow, px1 + shift * nx,
            py1 + shift * ny)


@kernel
def flipped(m):
    """Manifold m with its two shapes swapped: the normal reversed."""
    nx, ny, count, d0, px0, py0, d1, px1, py1 = m
    return -nx, -ny, count, d0, px0, py0, d1, px1, py1


@kernel
def capsule_circle(ax, ay, bx, by, ra, cx, cy, rc, margin):
    """The capsule of core a-b and radius ra against the circle (c, rc): the circle against
    the core's point nearest its centre. Normal from the capsule to the circle (the core's left
    side when the centre lies on the core)."""
    qx, qy, _ = closest_on_segment(cx, cy, ax, ay, bx, by)
    dx, dy = cx - qx, cy - qy
    distance = math.hypot(dx, dy)
    depth = ra + rc - distance
    if depth < -margin:
        return NONE
    if distance > 0.0:
        nx, ny = dx / distance, dy / distance
    else:
        length = math.hypot(bx - ax, by - ay)
        nx, ny = -(by - ay) / length, (bx - ax) / length
    reach = ra - 0.5 * depth   # midway between the two surfaces
    return nx, ny, 1, depth, qx + reach * nx, qy + reach * ny, 0.0, 0.0, 0.0


@kernel
def _clipped(p1x, p1y, ux, uy, length, nx, ny, p2x, p2y, q2x, q2y, ra, rb):
    """Segment p2-q2 clipped to the extent of the reference core p1 + [0, length]·u, whose
    normal n points toward it: its two ends as (depth, x, y) each, depth = ra + rb - (how far
    the end lies in front of the reference core along n), the point midway between surfaces."""
    f_p, f_q = (p2x - p1x) * ux + (p2y - p1y) * uy, (q2x - p1x) * ux + (q2y - p1y) * uy
    if f_q < f_p:
        p2x, p2y, q2x, q2y, f_p, f_q = q2x, q2y, p2x, p2y, f_q, f_p
    span = f_q - f_p
    lx, ly, hx, hy = p2x, p2y, q2x, q2y
    if span > 0.0:
        if f_p < 0.0:
            t = -f_p / span
            lx, ly = p2x + t * (q2x - p2x), p2y + t * (q2y - p2y)
        if f_q > length:
            t = (length - f_p) / span
            hx, hy = p2x + t * (q2x - p2x), p2y + t * (q2y - p2y)
    s_l = (lx - p1x) * nx + (ly - p1y) * ny
    s_h = (hx - p1x) * nx + (hy - p1y) * ny
    shift_l, shift_h = 0.5 * (ra - rb - s_l), 0.5 * (ra - rb - s_h)
    return (ra + rb - s_l, lx + shift_l * nx, ly + shift_l * ny, ra + rb - s_h, hx + shift_h * nx,
            hy + shift_h * ny)


@kernel
def _face_separation(px, py, nx, ny, ax, ay, bx, by):
    """How far segment a-b lies in front of the line through p along the normal n or -n
    (whichever it lies more in front of), and that normal: the separating-axis test of a core's
    two faces."""
    sa, sb = (ax - px) * nx + (ay - py) * ny, (bx - px) * nx + (by - py) * ny
    ahead, behind = min(sa, sb), min(-sa, -sb)
    return (ahead, nx, ny) if ahead > behind else (behind, -nx, -ny)


@kernel
def capsule_capsule(p1x, p1y, q1x, q1y, ra, p2x, p2y, q2x, q2y, rb, margin):
    """The capsule of core p1-q1 and radius ra against the capsule of core p2-q2 and radius rb
    (rb = 0: a thin segment), normal from the first to the second (Box2D v3's
    b2CollideCapsules). Cores that lie beside each other (each overlapping the other's extent
    along its axis) get the reference face of least overlap (the separating-axis test over the
    two cores' normals) and the other core clipped to it: two points, as two boxes' faces; a
    capsule lying on another gets both. Otherwise one point, on the line between the cores'
    closest points."""
    d1x, d1y, d2x, d2y = q1x - p1x, q1y - p1y, q2x - p2x, q2y - p2y
    ax, ay, bx, by = _closest_of_segments(p1x, p1y, d1x, d1y, p2x, p2y, d2x, d2y)
    dx, dy = bx - ax, by - ay
    distance = math.hypot(dx, dy)
    depth = ra + rb - distance
    if depth < -margin:
        return NONE
    len1, len2 = math.hypot(d1x, d1y), math.hypot(d2x, d2y)
    u1x, u1y, u2x, u2y = d1x / len1, d1y / len1, d2x / len2, d2y / len2
    f_p2, f_q2 = (p2x - p1x) * u1x + (p2y - p1y) * u1y, (q2x - p1x) * u1x + (q2y - p1y) * u1y
    f_p1, f_q1 = (p1x - p2x) * u2x + (p1y - p2y) * u2y, (q1x - p2x) * u2x + (q1y - p2y) * u2y
    outside_a = (f_p2 <= 0.0 and f_q2 <= 0.0) or (f_p2 >= len1 and f_q2 >= len1)
    outside_b = (f_p1 <= 0.0 and f_q1 <= 0.0) or (f_p1 >= len2 and f_q1 >= len2)
    if not outside_a and not outside_b:
        m = _beside(p1x, p1y, q1x, q1y, u1x, u1y, len1, ra, p2x, p2y, q2x, q2y, u2x, u2y, len2, rb, margin)
        # kept where the cores cross (the separating axis of least overlap), or where its face
        # is the cores' true separation (an end over the other's side): both ends then count
        if distance == 0.0 or abs(m[3] - depth) <= 1e-9 * (len1 + len2 + ra + rb):
            return m
    nx, ny = (dx / distance, dy / distance) if distance > 0.0 else (-u1y, u1x)
    reach = ra - 0.5 * depth
    return nx, ny, 1, depth, ax + reach * nx, ay + reach * ny, 0.0, 0.0, 0.0


@kernel
def _beside(p1x, p1y, q1x, q1y, u1x, u1y, len1, ra, p2x, p2y, q2x, q2y, u2x, u2y, len2, rb, margin):
    """Two capsules whose cores each overlap the other's extent along its axis: the reference
    face of least overlap (the separating-axis test over both cores' normals; a's on near ties,
    as Box2D) and the other core clipped to it, up to two points within the margin."""
    sep_a, nax, nay = _face_separation(p1x, p1y, -u1y, u1x, p2x, p2y, q2x, q2y)
    sep_b, nbx, nby = _face_separation(p2x, p2y, -u2y, u2x, p1x, p1y, q1x, q1y)
    if sep_b > sep_a + 1e-9 * (len1 + len2):
        d0, x0, y0, d1, x1, y1 = _clipped(p2x, p2y, u2x, u2y, len2, nbx, nby, p1x, p1y, q1x, q1y, rb, ra)
        nx, ny = -nbx, -nby
    else:
        d0, x0, y0, d1, x1, y1 = _clipped(p1x, p1y, u1x, u1y, len1, nax, nay, p2x, p2y, q2x, q2y, ra, rb)
        nx, ny = nax, nay
    if d1 > d0:
        d0, x0, y0, d1, x1, y1 = d1, x1, y1, d0, x0, y0
    if d1 < -margin or (x0 == x1 and y0 == y1):
        return nx, ny, 1, d0, x0, y0, 0.0, 0.0, 0.0
    return nx, ny, 2, d0, x0, y0, d1, x1, y1


@kernel
def _closest_of_segments(p1x, p1y, d1x, d1y, p2x, p2y, d2x, d2y):
    """The closest points (ax, ay, bx, by) of segments p1 + [0, 1]·d1 and p2 + [0, 1]·d2."""
    rx, ry = p1x - p2x, p1y - p2y
    dd1, dd2, d12 = d1x * d1x + d1y * d1y, d2x * d2x + d2y * d2y, d1x * d2x + d1y * d2y
    rd1, rd2 = rx * d1x + ry * d1y, rx * d2x + ry * d2y
    denominator = dd1 * dd2 - d12 * d12
    f1 = min(max((d12 * rd2 - rd1 * dd2) / denominator, 0.0), 1.0) if denominator != 0.0 else 0.0
    f2 = (d12 * f1 + rd2) / dd2
    if f2 < 0.0:
        f2, f1 = 0.0, min(max(-rd1 / dd1, 0.0), 1.0)
    elif f2 > 1.0:
        f2, f1 = 1.0, min(max((d12 - rd1) / dd1, 0.0), 1.0)
    return p1x + f1 * d1x, p1y + f1 * d1y, p2x + f2 * d2x, p2y + f2 * d2y


@compiled(error_model="numpy")
def rounded_cores(a, b, ra, rb, margin):
    """Shape a (k, 2), a polygon (ra = 0) or a capsule's core (k = 2) rounded by ra, against
    the capsule of core b (2, 2) rounded by rb: the cores' speculative manifold (as two
    polygons', narrowphase/polygons.py: speculative_polygons, with the margin grown by both
    radii) grown by the radii. Normal from a to b. Slices of the placed vertices, nothing
    allocated: the pair kernels run without numba's runtime."""
    m = speculative_polygons(a, b, margin + ra + rb)
    if m[2] == 0:
        return NONE
    return _grown(m, ra, rb)


@kernel
def capsule_halfplane(core, r, nx, ny, offset, margin):
    """The capsule of core (2, 2) and radius r against the solid half-plane {p : n·p <= offset}
    (n out of the solid; normal capsule to solid, -n): each cap centre nearer the line than r +
    margin is a point, midway between the cap's deepest point and the line."""
    grow = r + margin
    m = polygon_halfplane(core, nx, ny, offset + grow)   # the cap centres against the line moved out
    if m[2] == 0:
        return NONE
    # depths back by the margin; points from midway between centre and moved line to midway
    # between the surfaces: (grow + r)/2 further along the contact normal
    shift = 0.5 * (grow + r)
    return (m[0], m[1], m[2], m[3] - margin, m[4] + shift * m[0], m[5] + shift * m[1], m[6] - margin,
            m[7] + shift * m[0], m[8] + shift * m[1])


@kernel
def capsule_wall_manifold(radii, vertices, start, i, box, wall, margin):
    """The manifold of capsule body i and one box wall (normal into the wall)."""
    nx, ny, offset = box_wall_halfplane(box, wall)
    s = start[i]
    return capsule_halfplane(vertices[s:s + 2], capsule_radius(radii, vertices, start, i), nx, ny, offset, margin)


@kernel
def capsule_segment_manifold(radii, vertices, start, i, segments, k, margin):
    """The manifold of capsule body i and segment k of segments (m, 4) (normal from the capsule
    toward the segment): the segment is a capsule of radius 0."""
    s = start[i]
    return capsule_capsule(vertices[s, 0], vertices[s, 1], vertices[s + 1, 0], vertices[s + 1, 1],
                           capsule_radius(radii, vertices, start, i), segments[k, 0], segments[k, 1], segments[k, 2],
                           segments[k, 3], 0.0, margin)


@compiled(error_model="numpy")
def _with_capsule(shapes, positions, radii, vertices, start, i, j, margin):
    """The manifold of body i, any shape, and capsule j (normal from i to j)."""
    s = start[j]
    rb = capsule_radius(radii, vertices, start, j)
    if shapes[i] == CIRCLE:
        x0, y0, x1, y1 = vertices[s, 0], vertices[s, 1], vertices[s + 1, 0], vertices[s + 1, 1]
        return flipped(capsule_circle(x0, y0, x1, y1, rb, positions[i, 0], positions[i, 1], radii[i], margin))
    if shapes[i] == CAPSULE:
        r = start[i]
        return capsule_capsule(vertices[r, 0], vertices[r, 1], vertices[r + 1, 0], vertices[r + 1, 1],
                               capsule_radius(radii, vertices, start, i), vertices[s, 0], vertices[s, 1],
                               vertices[s + 1, 0], vertices[s + 1, 1], rb, margin)
    return rounded_cores(vertices[start[i]:start[i + 1]], vertices[s:s + 2], 0.0, rb, margin)   # a polygon


@compiled(error_model="numpy")
def capsule_pair_manifold(shapes, positions, radii, vertices, start, i, j, margin):
    """The manifold of bodies i and j, one of them (at least) a capsule (normal from i to j)."""
    if shapes[j] == CAPSULE:
        return _with_capsule(shapes, positions, radii, vertices, start, i, j, margin)
    return flipped(_with_capsule(shapes, positions, radii, vertices, start, j, i, margin))


@compiled(error_model="numpy")
def capsule_pair_touch(shapes, positions, radii, vertices, start, i, j):
    """Do bodies i and j, one of them a capsule, overlap or touch?"""
    if shapes[i] != CAPSULE:
        i, j = j, i
    s = start[i]
    ra = capsule_radius(radii, vertices, start, i)
    x0, y0, x1, y1 = vertices[s, 0], vertices[s, 1], vertices[s + 1, 0], vertices[s + 1, 1]
    if shapes[j] == CIRCLE:
        qx, qy, _ = closest_on_segment(positions[j, 0], positions[j, 1], x0, y0, x1, y1)
        return math.hypot(positions[j, 0] - qx, positions[j, 1] - qy) <= ra + radii[j]
    m = _with_capsule(shapes, positions, radii, vertices, start, j, i, 0.0)
    return m[2] > 0 and m[3] >= 0.0


@kernel
def capsule_pair_swept_gap(shapes, positions, radii, vertices, start, i, j, dx, dy):
    """The least gap between bodies i and j, one of them a capsule, while j moves by (dx, dy)
    relative to i (manifold.pair_swept_gap): the cores' sweep (a core is a two-vertex polygon,
    narrowphase/sweep.py) less the radii, a circle's with it."""
    ra = capsule_radius(radii, vertices, start, i) if shapes[i] == CAPSULE else 0.0   # a polygon's is 0
    rb = capsule_radius(radii, vertices, start, j) if shapes[j] == CAPSULE else 0.0
    if shapes[j] == CIRCLE:
        return swept_polygon_circle(vertices[start[i]:start[i + 1]], positions[j, 0], positions[j, 1], radii[j] + ra,
                                    dx, dy)
    if shapes[i] == CIRCLE:   # the capsule j seen from the circle i: the circle moves by -d
        return swept_polygon_circle(vertices[start[j]:start[j + 1]], positions[i, 0], positions[i, 1], radii[i] + rb,
                                    -dx, -dy)
    return swept_polygons(vertices[start[i]:start[i + 1]], vertices[start[j]:start[j + 1]], dx, dy) - ra - rb


@kernel
def ray_capsule_body(radii, vertices, start, i, ox, oy, ux, uy):
    """narrowphase/ray.py's test of capsule body i: (t, nx, ny, inside)."""
    s = start[i]
    return ray_capsule(ox, oy, ux, uy, vertices[s, 0], vertices[s, 1], vertices[s + 1, 0], vertices[s + 1, 1],
                       capsule_radius(radii, vertices, start, i))
