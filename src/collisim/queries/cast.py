"""The compiled loop behind raycast_many: m rays, one call, the structures built once.

Each ray starts from the statics, which are cheap and give the search a finite limit at once
(a ray from inside the box always leaves it): the walls, the map's solid if the origin lies in
it, the world's segments and the map's contour segments (each through its segment index).
The broad phase then searches the bodies for anything closer (broadphase/ray_closest.py).
"""
import math

import numpy as np

from ..broadphase.ray_closest import body_ray_closest
from ..broadphase.ray_hit import MAP, SEGMENT, WALL, Ray, keep_closer, no_hit
from ..core.compiling import compiled, kernel
from ..core.geometry.ray import ray_walls
from .segment_rays import nearest_segment, segment_ray_closest


@kernel
def unit_directions(origins, directions, max_distances, units):
    """Fill units (m, 2) with the directions (m, 2) divided by their lengths, as check_ray
    does for one ray (components near the float64 limit halved first, which is exact, so the
    length does not overflow). Returns the first ray check_ray would refuse, or -1."""
    for k in range(origins.shape[0]):
        dx, dy = directions[k, 0], directions[k, 1]
        finite = np.isfinite(origins[k, 0]) and np.isfinite(origins[k, 1]) and np.isfinite(dx) and np.isfinite(dy)
        if not (finite and (dx != 0.0 or dy != 0.0) and max_distances[k] >= 0.0):
            return k
        length = math.hypot(dx, dy)
        if length == np.inf:
            dx, dy = 0.5 * dx, 0.5 * dy
            length = math.hypot(dx, dy)
        units[k, 0], units[k, 1] = dx / length, dy / length
    return -1


@compiled(inline="always")
def statics_closest(box, segments, map_segments, in_map, ray):
    """The first hit among the statics. box: (4,); segments, map_segments: SegmentGrid; in_map:
    the origin lies in the map's solid (its index is then the nearest map segment)."""
    t, wall, nx, ny, inside = ray_walls(ray.ox, ray.oy, ray.ux, ray.uy, box)
    best = keep_closer(no_hit(), t, inside, WALL, wall, nx, ny, ray.max_distance)
    if in_map:
        nearest = nearest_segment(map_segments.segments, ray.ox, ray.oy)
        best = keep_closer(best, 0.0, True, MAP, nearest, 0.0, 0.0, ray.max_distance)
    best = segment_ray_closest(segments, SEGMENT, ray, best)
    return segment_ray_closest(map_segments, MAP, ray, best)


@kernel
def record(out, k, ray, best):
    """Write hit `best` of ray k into the output arrays (nothing hit: distance inf, point and
    normal nan, kind and index -1)."""
    distance, points, normals, kinds, indices, inside, _, _ = out
    t, is_inside, kind, index, nx, ny = best
    distance[k] = t
    points[k, 0] = ray.ox + t * ray.ux if t < np.inf else np.nan
    points[k, 1] = ray.oy + t * ray.uy if t < np.inf else np.nan
    normals[k, 0], normals[k, 1] = nx + 0.0, ny + 0.0  # -0.0 (a negated zero component) reads as 0
    kinds[k], indices[k], inside[k] = kind, index, is_inside


@compiled
def cast_rays(state, bodies, box, segments, map_segments, in_map, origins, units, max_distances, scale, skip_inside,
              out):
    """The closest hit of each ray origins[k] + t·units[k], t in [0, max_distances[k]].

    state: the broad phase's ray structure (registry.ray_state); bodies: (shapes (n,), positions (n, 2),
    radii (n,), lo (n, 2), hi (n, 2)), lo and hi their bounding boxes; box: (4,); segments, map_segments: SegmentGrid; in_map: (m,) bool; origins,
    units: (m, 2); max_distances: (m,); scale: the largest world coordinate (for the pruning
    slack); skip_inside: bodies holding a ray's origin are looked past; out: the arrays of a
    RayHits (distance, points, normals, kinds, indices, inside,
    visited, tested), filled in place.
    """
    visited, tested = out[6], out[7]
    for k in range(origins.shape[0]):
        ox, oy = origins[k, 0], origins[k, 1]
        ray = Ray(ox, oy, units[k, 0], units[k, 1], max_distances[k], scale + abs(ox) + abs(oy), skip_inside)
        best = statics_closest(box, segments, map_segments, in_map[k], ray)
        best, visited[k], tested[k] = body_ray_closest(state, bodies, ray, best)
        record(out, k, ray, best)
