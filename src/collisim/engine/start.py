"""Where the engine starts: a scene it cannot run is one clear line (ValueError) before any step.

The model checks each value as it is given (core/checks.py); what needs the engine's own tables
is checked here, once per scene, before anything is simulated or written: the method and the
broad phase by name (their registries), and the initial state's overlaps by the narrow phase.
Bodies that start inside each other, or inside a segment or the map, have no defined contact
normal or order of events, so every method would silently do something different. Touching is
allowed (within a relative 1e-9, so bodies placed touching by arithmetic pass).
"""
from __future__ import annotations

import numpy as np

from ..broadphase import NAMES as BROAD_PHASES
from ..core.kinds import CAPSULE, CIRCLE, POLYGON, capsules_flag
from ..narrowphase.manifold import shape_segment_manifold
from ..narrowphase.statics import touching_segments
from ..queries.contacts import contacts

TOUCH_TOLERANCE = 1e-9   # relative to the contact distance
BRUTE_FORCE = 256   # circles checked pair by pair in numpy (_first_overlap)


def check_scene(scene, methods) -> None:
    """ValueError for the first thing in scene (its panels and chapters included) that the
    engine cannot run: a method not in `methods`, an unknown broad phase, friction or damping
    under ccd (which would otherwise be left out without a word), bodies that overlap."""
    for part in (*(panel.scene for panel in scene.panels), *scene.chapters):
        check_scene(part, methods)
    if scene.method not in methods:
        raise ValueError(f"unknown method {scene.method!r}; choose one of: {', '.join(methods)}")
    if scene.broadphase not in ("auto",) + BROAD_PHASES:
        raise ValueError(f"unknown broad phase {scene.broadphase!r}; choose one of: auto, "
                         f"{', '.join(BROAD_PHASES)}")
    if scene.world is not None:
        if scene.method == "ccd":
            check_ccd_covers(scene.world)
        no_overlaps(scene.world)


def check_ccd_covers(world) -> None:
    """ValueError, in one line, for a world the event-driven method does not model, which it
    would otherwise run without a word: polygons, capsules, gravity that differs from body to body,
    friction, damping. (It moves circles exactly along parabolas between frictionless impacts.)"""
    if np.any(world.shapes == CAPSULE):
        raise ValueError("method ccd covers circles, segments and maps; this scene has capsules: use method discrete")
    if np.any(world.shapes == POLYGON):
        raise ValueError("method ccd covers circles, segments and maps; this scene has polygons: use method discrete")
    if not world.uniform_acceleration:
        raise ValueError("method ccd needs one uniform gravity for all particles")
    if world.friction > 0.0:
        raise ValueError(f"method ccd covers frictionless contacts only (bodies slide without turning); this world "
                         f"has friction={world.friction:g}: use method discrete, or friction=0")
    if world.damping < 1.0:
        raise ValueError(f"method ccd moves bodies exactly along parabolas and does not model damping "
                         f"(damping={world.damping:g}): use method discrete")


def no_overlaps(world) -> None:
    """ValueError naming the first pair of bodies, or body and segment, that overlap."""
    if world.n >= 2:
        overlap = _first_overlap(world)
        if overlap is not None:
            i, j, depth = overlap
            raise ValueError(f"bodies {i} and {j} overlap by {depth:.3g} at the start; place them apart or touching")
    if len(world.segments):
        pairs, depths = touching_segments(world.positions, world.radii, world.segments, world.box)
        depths = _polygon_depths(world, pairs, depths)
        deep = np.flatnonzero(depths > world.radii[pairs[:, 0]] * TOUCH_TOLERANCE)
        if deep.size:
            i, s = pairs[deep[0]]
            raise ValueError(f"body {i} overlaps segment {s} by {depths[deep[0]]:.3g} at the start; "
                             f"place it apart or touching")
    if world.map is not None:
        _outside_map(world)


def _first_overlap(world):
    """(i, j, depth) of the first pair of bodies, in (i, j) order, that overlap by more than the
    tolerance, or None. A world of at most BRUTE_FORCE circles is checked pair by pair in numpy:
    the contacts query (queries/contacts.py) compiles the grid and the contact table for Python,
    about 2 s of a first run's first frame spent before the step even starts compiling. Every
    pair at once costs n²: 0.7 ms at 250 circles, where the compiled query takes 0.1 ms once
    compiled (23 ms at 1 000)."""
    if world.n > BRUTE_FORCE or np.any(world.shapes != CIRCLE):
        found = contacts(world)
        pairs, depths = found["pairs"], found["depths"]
        deep = np.flatnonzero(depths > world.radii[pairs].sum(axis=1) * TOUCH_TOLERANCE)
        return None if deep.size == 0 else (*pairs[deep[0]], depths[deep[0]])
    x, y, radii = world.positions[:, 0], world.positions[:, 1], world.radii
    reach = radii[:, None] + radii[None, :]
    later = np.arange(world.n)[None, :] > np.arange(world.n)[:, None]   # (i, j > i)
    near = np.argwhere(later & ((x[None, :] - x[:, None]) ** 2 + (y[None, :] - y[:, None]) ** 2 < (1.5 * reach) ** 2))
    i, j = near[:, 0], near[:, 1]   # in (i, j) order; their exact depths, as circle_circle computes them
    depth = reach[i, j] - np.hypot(x[j] - x[i], y[j] - y[i])
    deep = np.flatnonzero(depth > reach[i, j] * TOUCH_TOLERANCE)
    return None if deep.size == 0 else (int(i[deep[0]]), int(j[deep[0]]), float(depth[deep[0]]))


def _polygon_depths(world, pairs, depths):
    """depths of (body, segment) pairs found by bounding circles, exact for polygons and capsules."""
    polygons = np.flatnonzero(world.shapes[pairs[:, 0]] != CIRCLE)   # polygons and capsules
    if polygons.size == 0:
        return depths
    depths, vertices = depths.copy(), world.placed_vertices()
    capsules = capsules_flag(world.shapes)
    for row in polygons:   # a start-up check, once per world: not a hot path
        m = shape_segment_manifold(world.shapes, world.radii, vertices, world.vertex_start, pairs[row, 0],
                                   world.segments, pairs[row, 1], 0.0, capsules)
        depths[row] = m[3] if m[2] > 0 else -1.0
    return depths


def _outside_map(world) -> None:
    """ValueError naming the first body that starts inside the collision map's solid, or
    overlapping its contour chains (which ccd collides with exactly)."""
    depths = world.radii - world.map.distance(world.positions)
    # the distance field is exact only to about a cell: its own tolerance is half a cell
    deep = np.flatnonzero(depths > 0.5 * world.map.cell + world.radii * TOUCH_TOLERANCE)
    if deep.size:
        i = deep[0]
        raise ValueError(f"body {i} at ({world.positions[i, 0]:g}, {world.positions[i, 1]:g}) starts inside the "
                         f"collision map's solid; place it in free space")
    pairs, depths = touching_segments(world.positions, world.radii, world.map.segments, world.box)
    deep = np.flatnonzero(depths > world.radii[pairs[:, 0]] * TOUCH_TOLERANCE)
    if deep.size:
        i = pairs[deep[0], 0]
        raise ValueError(f"body {i} overlaps the collision map's outline by {depths[deep[0]]:.3g} at the start; "
                         f"place it in free space")
