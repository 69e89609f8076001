"""Convex polygons: mass properties, placing body vertices in the world, and bounding shapes.

A polygon body keeps its vertices in the body frame, (k, 2) counter-clockwise with the centre of
mass at the origin (shapes.convex_polygon validates a user's polygon; polygon_mass_properties
finds the centroid to subtract). Each step places them in the world with world_vertices.
Edge i runs from vertex i to vertex i + 1 (the last back to vertex 0); for a counter-clockwise
polygon its outward normal is the edge direction turned clockwise, (ey, -ex) / |e|.

Bounding shapes, from cheapest to tightest: the bounding circle (bounding_radius), the
axis-aligned box (polygon_bounds), the oriented box (oriented_box), then the polygon itself.
"""
import math

import numpy as np

from ..compiling import compiled, kernel


def _fan_moments(vertices, reference):
    """Area, first moment (2,) and polar second moment of a polygon about `reference`, summed
    over the triangles (reference, v_i, v_i+1). Working relative to a reference point near the
    polygon keeps the products small, so a polygon far from the origin loses no digits.
    vertices: (k, 2) counter-clockwise; reference: (2,)."""
    e1 = vertices - reference
    e2 = np.roll(e1, -1, axis=0)
    cross = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]          # twice each triangle's area
    area = 0.5 * cross.sum()
    first = (cross[:, None] * (e1 + e2)).sum(axis=0) / 6.0      # area · triangle centroid
    # ∫|p|² dA over a triangle with one vertex at the reference (Box2D's b2ComputePolygonMass)
    second = (cross * ((e1 * e1).sum(1) + (e1 * e2).sum(1) + (e2 * e2).sum(1))).sum() / 12.0
    return area, first, second


def polygon_mass_properties(vertices, density=1.0):
    """(mass, centroid (2,), inertia about the centroid) of a uniform solid polygon.
    vertices: (k, 2) counter-clockwise (shapes.convex_polygon); density: mass per unit area.
    The centroid comes from a fan about vertex 0, the inertia from a second fan about the
    centroid itself, so no parallel-axis subtraction can cancel digits."""
    vertices = np.asarray(vertices, np.float64)
    area, first, _ = _fan_moments(vertices, vertices[0])
    centroid = vertices[0] + first / area
    _, _, second = _fan_moments(vertices, centroid)
    return density * area, centroid, density * second


def circle_inertia(mass, radius):
    """Moment of inertia of a solid disc about its centre: ½·m·r² (scalars or arrays)."""
    return 0.5 * mass * radius * radius


@compiled(error_model="numpy")
def world_vertices(body_vertices, x, y, angle, out):
    """Rotate body_vertices (k, 2) by `angle` (counter-clockwise radians) about the body origin,
    move them to (x, y) and write them into out (k, 2). Returns out."""
    c, s = math.cos(angle), math.sin(angle)
    for i in range(body_vertices.shape[0]):
        bx, by = body_vertices[i, 0], body_vertices[i, 1]
        out[i, 0] = x + c * bx - s * by
        out[i, 1] = y + s * bx + c * by
    return out


@compiled(error_model="numpy")
def place_polygons(body_vertices, vertex_start, positions, angles, out):
    """Every polygon's vertices in the world at these poses, into out (V, 2): body i's are
    body_vertices[vertex_start[i]:vertex_start[i + 1]] (none for a circle). Returns out."""
    for i in range(positions.shape[0]):
        s, e = vertex_start[i], vertex_start[i + 1]
        if e > s:
            world_vertices(body_vertices[s:e], positions[i, 0], positions[i, 1], angles[i], out[s:e])
    return out


@compiled(error_model="numpy")
def place_any_polygons(polygons, body_vertices, vertex_start, positions, angles, out):
    """place_polygons where the world has polygons (polygons: core/kinds.shapes_flag, None for a
    world of circles alone, whose step then compiles none of it: numba prunes the branch on a
    None argument)."""
    if polygons is not None:
        place_polygons(body_vertices, vertex_start, positions, angles, out)


@kernel
def polygon_bounds(vertices):
    """The axis-aligned box (xmin, ymin, xmax, ymax) around vertices (k, 2)."""
    xmin, ymin = vertices[0, 0], vertices[0, 1]
    xmax, ymax = xmin, ymin
    for i in range(1, vertices.shape[0]):
        xmin, xmax = min(xmin, vertices[i, 0]), max(xmax, vertices[i, 0])
        ymin, ymax = min(ymin, vertices[i, 1]), max(ymax, vertices[i, 1])
    return xmin, ymin, xmax, ymax


@compiled(error_model="numpy")
def edge_normals(vertices, out):
    """Unit outward normals of a counter-clockwise polygon's edges into out (k, 2): row i is
    the normal of the edge from vertex i to vertex i + 1. Returns out."""
    k = vertices.shape[0]
    for i in range(k):
        j = i + 1 if i + 1 < k else 0
        ex, ey = vertices[j, 0] - vertices[i, 0], vertices[j, 1] - vertices[i, 1]
        length = math.hypot(ex, ey)
        out[i, 0], out[i, 1] = ey / length, -ex / length
    return out


@kernel
def bounding_radius(body_vertices):
    """The radius of the smallest circle about the body origin (the centroid) holding every
    vertex: max |v| over body_vertices (k, 2)."""
    reach = 0.0
    for i in range(body_vertices.shape[0]):
        reach = max(reach, math.hypot(body_vertices[i, 0], body_vertices[i, 1]))
    return reach


@kernel
def _farthest_along(vertices, start, ux, uy):
    """Walk forward (counter-clockwise) from vertex `start` while the next vertex lies further
    along (ux, uy); the index where it stops. Along a convex polygon the projection rises to
    one maximum and falls, so a walk from before the maximum stops exactly on it."""
    k = vertices.shape[0]
    i = start
    for _ in range(k):                      # at most once round: no endless walk on ties
        j = i + 1 if i + 1 < k else 0
        if vertices[j, 0] * ux + vertices[j, 1] * uy <= vertices[i, 0] * ux + vertices[i, 1] * uy:
            break
        i = j
    return i


@kernel
def oriented_box(body_vertices):
    """The minimum-area rectangle around a convex counter-clockwise polygon (k, 2):
    (cx, cy, half_w, half_h, angle) — its centre, its half extents along its own axes, and the
    angle (counter-clockwise radians) of the half_w axis, all in the body frame.

    Rotating calipers (Freeman and Shapira; Toussaint): the best rectangle has a side on one
    of the polygon's edges. For each edge in turn, three calipers mark the vertices farthest
    along the edge, farthest from it, and farthest back; as the edge direction turns
    counter-clockwise each caliper only moves forward, so all edges cost O(k) together."""
    v = body_vertices
    k = v.shape[0]
    best_area = np.inf
    cx = cy = half_w = half_h = angle = 0.0
    ahead, far, behind = 1 % k, 1 % k, 1 % k
    for i in range(k):
        j = i + 1 if i + 1 < k else 0
        ex, ey = v[j, 0] - v[i, 0], v[j, 1] - v[i, 1]
        length = math.hypot(ex, ey)
        ux, uy = ex / length, ey / length           # along the edge; -uy, ux points inside
        if i == 0:                                  # each caliper starts where the last stopped
            ahead = _farthest_along(v, j, ux, uy)
            far = _farthest_along(v, ahead, -uy, ux)
            behind = _farthest_along(v, far, -ux, -uy)
        else:
            ahead = _farthest_along(v, ahead, ux, uy)
            far = _farthest_along(v, far, -uy, ux)
            behind = _farthest_along(v, behind, -ux, -uy)
        lo = v[behind, 0] * ux + v[behind, 1] * uy
        hi = v[ahead, 0] * ux + v[ahead, 1] * uy
        base = v[i, 0] * -uy + v[i, 1] * ux
        top = v[far, 0] * -uy + v[far, 1] * ux
        area = (hi - lo) * (top - base)
        if area < best_area:
            best_area = area
            along, across = 0.5 * (lo + hi), 0.5 * (base + top)
            cx, cy = along * ux - across * uy, along * uy + across * ux
            half_w, half_h, angle = 0.5 * (hi - lo), 0.5 * (top - base), math.atan2(uy, ux)
    return cx, cy, half_w, half_h, angle
