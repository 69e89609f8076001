"""Ray queries: the first thing a ray hits in a world, the point where it hits, and the surface
normal there (`checkRayCollision(position, dir, length, out cp, out surfaceNormal)`).

What a ray can hit, and what the answer says (geometry/ray.py has each shape's exact rule):

* bodies (kind "body", index the body): solid, circles and convex polygons alike. A ray whose
  origin is strictly inside one (|o - c| < r for a circle) returns distance 0, point = origin, normal (0, 0), inside True.
  Engines differ here: pymunk's segment_query_first reports a hit at alpha 0 whose point and
  normal describe no surface; Box2D's ray casts treat initial overlap as a miss and look past
  the shape. Here you are told, and can step out and cast again for what lies beyond. An
  origin exactly on a circle hits it at distance 0 with the outward normal when the ray points
  into it or along it (tangent: touching counts); pointing away, that circle is not hit;
* the walls (kind "wall", index the side 0..3 in kinds.WALL_SIDES order: left, right, bottom,
  top): everything outside the world box is solid. A ray from inside hits the wall it leaves
  through, normal pointing back into the box; an origin outside the box is inside (distance 0,
  inside True, the first wall in that order whose outside holds it). An origin on a wall
  pointing out of the box, or along the wall, touches it at distance 0;
* segments (kind "segment", index the row of world.segments): thin and two-sided; the normal
  is the segment's perpendicular on the ray's side. An origin on a segment hits it at distance 0
  (inside False). A ray running along a segment's own line hits it at the nearer end point, or
  at 0 if it starts on it, with normal -direction (the segment's end, seen edge on);
* the collision map, if the world has one (kind "map"): its contour segments are hit like
  segments (index the row of map.segments); an origin where map.distance < 0 is inside (index
  the nearest map segment).

The distance is measured along the unit direction and the interval is closed: a surface at
exactly max_distance is hit. Touching counts (a ray grazing a circle hits it at the tangent
point). Hits at equal distances are decided in one canonical order, whichever broad phase
searched: inside before on a surface, then body < segment < map < wall, then the smaller index.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ..broadphase import NAMES
from ..broadphase._rays import check_ray
from ..broadphase.registry import AUTO, choose, ray_state
from ..broadphase.ray_hit import HIT_KINDS
from .segment_rays import segment_grid
from .cast import cast_rays, unit_directions

KIND_NAMES = HIT_KINDS  # code -> name; -1 is no hit


@dataclass(frozen=True, eq=False)
class RayHit:
    """The first hit of one ray. point, normal: (2,) read-only; normal is a unit vector facing
    the ray (normal · direction <= 0), or (0, 0) when inside. kind: "body", "segment", "map" or
    "wall"; index: the body, segment row, map segment row, or wall side (kinds.WALL_SIDES)."""
    distance: float
    point: np.ndarray
    normal: np.ndarray
    kind: str
    index: int
    inside: bool


@dataclass(frozen=True, eq=False)
class RayHits:
    """The first hits of m rays, as arrays.

    distance (m,) float64: inf where nothing is hit; points, normals (m, 2): nan there;
    kinds (m,) int8: codes into KIND_NAMES, -1 for no hit; indices (m,) int64, -1 for no hit;
    inside (m,) bool; visited (m,) int64: the nodes, cells or boxes the broad phase examined;
    tested (m,) int64: the bodies it tested exactly (segments and walls not counted).
    broadphase: the broad phase that searched the bodies.
    """
    distance: np.ndarray
    points: np.ndarray
    normals: np.ndarray
    kinds: np.ndarray
    indices: np.ndarray
    inside: np.ndarray
    visited: np.ndarray
    tested: np.ndarray
    broadphase: str
    KIND_NAMES: ClassVar[tuple[str, ...]] = KIND_NAMES

    def __len__(self) -> int:
        return len(self.distance)

    def hit(self, k: int) -> RayHit | None:
        """Ray k's hit as a RayHit, or None if it hits nothing."""
        if self.kinds[k] < 0:
            return None
        point, normal = self.points[k].copy(), self.normals[k].copy()
        point.flags.writeable = normal.flags.writeable = False
        return RayHit(float(self.distance[k]), point, normal, KIND_NAMES[self.kinds[k]],
                      int(self.indices[k]), bool(self.inside[k]))


def raycast(world, origin, direction, max_distance=math.inf, broadphase=AUTO, *,
            positions=None, angles=None, skip_inside=False) -> RayHit | None:
    """The first thing the ray origin + t·u, t in [0, max_distance], u = direction / |direction|,
    hits in `world`, or None (see the module docstring for what counts as a hit).

    origin, direction: (2,); max_distance >= 0, inf allowed; broadphase: "auto" or one of
    broadphase.NAMES (all give the same answer); positions: (n, 2) body centres, and angles (n,)
    the polygons' turns, to use instead of the world's own (a recorded frame). A ray starting
    inside a body (a circle or a polygon), the map's solid or
    outside the box returns distance 0, point = origin, normal (0, 0), inside True; with
    skip_inside=True a body holding the origin is looked past instead (Box2D's rule), and the
    ray reports what lies beyond it (the map's solid and the box still count as inside). Raises
    ValueError for a zero or non-finite direction, a non-finite origin, or a negative or NaN
    max_distance.
    """
    check_ray(origin, direction, max_distance)
    hits = raycast_many(world, np.reshape(origin, (1, 2)), np.reshape(direction, (1, 2)), max_distance,
                        broadphase, positions=positions, angles=angles, skip_inside=skip_inside)
    return hits.hit(0)


def raycast_many(world, origins, directions, max_distance=math.inf, broadphase=AUTO, *,
                 positions=None, angles=None, skip_inside=False) -> RayHits:
    """The first hits of m rays, in one compiled call: the broad phase's structure and the
    segment indices are built once.

    origins, directions: (m, 2); max_distance: a number or (m,), each >= 0, inf allowed;
    broadphase, positions, angles, skip_inside: as for raycast. Raises ValueError, naming the ray, for a bad one.
    """
    origins, units, max_distances = check_rays(origins, directions, max_distance)
    name = broadphase_name(world, broadphase)
    bodies = body_arrays(world, positions, angles)
    lo, hi = bodies[-2], bodies[-1]
    segments, map_segments, in_map = statics_arrays(world, origins)
    m = len(origins)
    out = (np.empty(m), np.empty((m, 2)), np.empty((m, 2)), np.empty(m, np.int8), np.empty(m, np.int64),
           np.empty(m, bool), np.empty(m, np.int64), np.empty(m, np.int64))
    scale = world_scale(world.box, lo, hi, segments.segments, map_segments.segments)
    cast_rays(ray_state(name, lo, hi), bodies, np.asarray(world.box, np.float64), segments, map_segments, in_map,
              origins, units, max_distances, scale, bool(skip_inside), out)
    return RayHits(*out, broadphase=name)


def check_rays(origins, directions, max_distance) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """origins (m, 2), unit directions (m, 2) and max distances (m,) as C-contiguous float64, or
    ValueError: shapes in one line, a bad ray in check_ray's words, prefixed with its number."""
    origins = np.ascontiguousarray(origins, dtype=np.float64)
    directions = np.ascontiguousarray(directions, dtype=np.float64)
    if origins.ndim != 2 or origins.shape[1:] != (2,) or directions.shape != origins.shape:
        raise ValueError(f"origins and directions must both have shape (m, 2); "
                         f"got {origins.shape} and {directions.shape}")
    m = len(origins)
    try:
        max_distances = np.array(max_distance, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"max_distance must be a number or one number per ray; got {max_distance!r}") from None
    if max_distances.shape not in ((), (m,)):
        raise ValueError(f"max_distance must be a number or have shape ({m},); got shape {max_distances.shape}")
    # a copy, always: one ray's broadcast number would be a read-only view, another type to numba,
    # and unit_directions and cast_rays would compile twice (raycast's one ray, raycast_many's)
    max_distances = np.broadcast_to(max_distances, (m,)).copy()
    units = np.empty((m, 2))
    bad = unit_directions(origins, directions, max_distances, units)
    if bad >= 0:
        try:
            check_ray(origins[bad], directions[bad], max_distances[bad])
        except ValueError as error:
            raise ValueError(f"ray {bad}: {error}") from None
        raise ValueError(f"ray {bad} is not a valid ray")  # unreachable while both agree
    return origins, units, max_distances


def broadphase_name(world, broadphase: str) -> str:
    """The broad phase to search with: `broadphase`, or for "auto" the one step.choose picks."""
    if broadphase == AUTO:
        return choose(world)
    if broadphase not in NAMES:
        raise ValueError(f"unknown broad phase {broadphase!r}; choose one of: {AUTO}, {', '.join(NAMES)}")
    return broadphase


def body_arrays(world, positions, angles=None) -> tuple[np.ndarray, ...]:
    """(shapes (n,) int8, centres (n, 2), radii (n,), vertices (V, 2), start (n + 1,), lo (n, 2),
    hi (n, 2)): the bodies at world.positions and world.angles, or at `positions` and `angles`,
    the polygons' vertices placed there, and the bounding boxes of their bounding circles."""
    centres = world.positions if positions is None else np.asarray(positions, dtype=np.float64)
    if centres.shape != (world.n, 2):
        raise ValueError(f"positions must have shape ({world.n}, 2); got {centres.shape}")
    if not np.isfinite(centres).all():
        raise ValueError("positions must be finite (no NaN or inf)")
    centres = np.ascontiguousarray(centres, dtype=np.float64)
    turns = world.angles if angles is None else np.asarray(angles, dtype=np.float64)
    if turns.shape != (world.n,) or not np.isfinite(turns).all():
        raise ValueError(f"angles must be {world.n} finite numbers; got shape {turns.shape}")
    vertices = world.placed_vertices(centres, np.ascontiguousarray(turns))
    radii = np.ascontiguousarray(world.radii, dtype=np.float64)
    reach = radii[:, None]
    return (np.ascontiguousarray(world.shapes, dtype=np.int8), centres, radii, vertices,
            np.ascontiguousarray(world.vertex_start, dtype=np.int64), centres - reach, centres + reach)


def statics_arrays(world, origins) -> tuple:
    """The world's segments and the map's contour segments, each indexed (SegmentGrid), and
    (m,) bool: which origins lie in the map's solid (map.distance < 0). No map: no segments."""
    world_map = getattr(world, "map", None)
    segments = segment_grid(world.segments, world.box)
    map_segments = segment_grid(np.zeros((0, 4)) if world_map is None else world_map.segments, world.box)
    in_map = np.zeros(len(origins), bool)
    if len(map_segments.segments) and len(origins):
        in_map = np.asarray(world_map.distance(origins), np.float64).reshape(len(origins)) < 0.0
    return segments, map_segments, in_map


def world_scale(box, lo, hi, *segment_arrays) -> float:
    """The largest coordinate magnitude in the world: the scale of its rounding errors."""
    parts = [np.abs(np.asarray(box, np.float64)), np.abs(lo).ravel(), np.abs(hi).ravel()]
    parts += [np.abs(segments).ravel() for segments in segment_arrays]
    return float(max(part.max(initial=0.0) for part in parts))
