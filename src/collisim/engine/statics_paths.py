"""The statics a world may lack — segments, a collision map — compiled only for worlds that have them.

The discrete step's Statics holds None for what its world lacks: no segment index without
segments, no field without a collision map. Each function below is one name whose
implementation numba picks by the type of that field when the step compiles (as
broadphase/step.py picks the broad phase): a no-op for None. So a world of bodies in a box
never compiles the segment index, the segment contacts and bounces, nor the map's march,
bounce and push-out — about forty compiles that a first run of particles_250 paid for paths it
never takes. A world with segments or a map compiles its own step, cached on its own. A field
given anyway (no_map_field(), an empty index) takes the full path with its run-time checks.
"""
import numpy as np
from numba.core import types
from numba.extending import overload

from ..core.arrays import copy_rows, grown
from ..core.compiling import compiled, inlined, kernel
from ..core.geometry.box import centre_range
from ..core.geometry.vector import length
from ..core.kinds import CIRCLE, MAP, N_WALLS, SEGMENT, WALL
from ..narrowphase.statics import circle_segment, segment_contacts
from ..response.map import bounce_off_map, glide_past_map, push_out
from ..response.rows import (MARGIN, beyond_segment, circle_map_manifold, circle_segment_manifolds, near_segments,
                              segment_manifolds)
from ..response.statics import bounce_between_walls, bounce_off_segment, put_on_segment
from ..statics.map_field import has_map, map_sample
from ..statics.segment_index import segments_near
from .eventlog import append, with_room


# columns of statics_scratch's held (n, 5) after the two axes of the walls: held by a segment, by the
# map, and near a segment at the end of the step (the segment phase's contacts: touching, or apart
# by at most rows.MARGIN of the radius, the smallest speculative margin). Near, not touching: a
# disc the solver held on a segment ends its step on it only within rounding, on either side;
# looked up again only where it ended inside, a sliding disc missed its rows at every step that
# ended a rounding error outside, fell into the segment and took the frictionless bounce, logged
# as a collision, on as many as a third of the frames down a slope.
HELD_BY_SEGMENT, HELD_BY_MAP, NEAR_SEGMENT = 2, 3, 4
LOW_SIDE, HIGH_SIDE = np.int64(0), np.int64(1)   # a wall's side on its axis (numpy: one compile for both)


def _lacks(statics_type, field: str) -> bool:
    """Whether field of a Statics namedtuple type is None (the world lacks it)."""
    return isinstance(statics_type.types[statics_type.fields.index(field)], types.NoneType)


def segment_phase(bodies, statics, scratch, log, now, frame_collisions):
    """Bounce bodies off the segments they touch, in place (compiled code only): each bounce
    counted in frame_collisions[SEGMENT] and logged. scratch from statics_scratch.
    Returns the log."""
    raise NotImplementedError("segment_phase is called from compiled code")


def circle_segment_rows(bodies, statics, margin, in_pair, held, found, k, asleep):
    """Record after found[:k] the manifolds of the circles held by segments (compiled code only;
    response/rows.circle_segment_manifolds), found grown as needed; sleepers have none, as for
    the walls. Only the circles that could be held look for their segments in the index: those
    in a pair's manifold, no faster than the rest speed, or near a segment at the end of the
    step before (held[:, NEAR_SEGMENT], from the segment phase's own lookup: a ball rolling or
    sliding down a slope). A lone fast circle in free flight cannot rest on a segment, and the segment
    bounce takes its impact (looking up every circle's segments twice a step made a gas among
    segments cost 4.0 x the gas alone, against 2.0 x). Returns (found, the new record count)."""
    raise NotImplementedError("circle_segment_rows is called from compiled code")


def polygon_segment_rows(bodies, statics, vertices, margin, found, k, asleep):
    """Record after found[:k] the manifolds of the polygons within `margin` (fast_polygons'
    segment_reach) of a segment (compiled code only; response/rows.segment_manifolds), found
    grown as needed; nothing in a world without polygons or without segments. Returns (found,
    the new record count)."""
    raise NotImplementedError("polygon_segment_rows is called from compiled code")


def circle_map_rows(bodies, statics, margin, in_pair, found, k, asleep):
    """Record after found[:k] the manifolds of the awake circles held by the collision map
    (compiled code only; response/rows.circle_map_manifold: one sample of the map a circle).
    Returns (found, the new record count)."""
    raise NotImplementedError("circle_map_rows is called from compiled code")


def may_turn(bodies, statics, dt, turns):
    """Which bodies a static may turn within the step of dt: turns (n,) bool, True where a body's
    bounding circle, moved as far as it can go in the step, reaches a box wall, a segment or the
    map (compiled code only). Only those can meet, in mid-step, a body the near-miss sweep let
    pass on a straight line (response/pair_rows.py: _may_meet). Returns turns."""
    raise NotImplementedError("may_turn is called from compiled code")


@overload(may_turn)
def _may_turn(bodies, statics, dt, turns):
    # what the world lacks is not compiled (the branches on these constants are pruned)
    with_segments, with_map = not _lacks(statics, "index"), not _lacks(statics, "map")

    def reach_statics(bodies, statics, dt, turns):
        box, segments = statics.box, statics.segments
        near = np.empty(segments.shape[0] + 1, np.int64)   # the segments the index has near a body
        for i in range(turns.shape[0]):
            reach = _travel(bodies, dt, i)
            x, y = bodies.positions[i, 0], bodies.positions[i, 1]
            turns[i] = x - reach <= box[0] or y - reach <= box[1] or x + reach >= box[2] or y + reach >= box[3]
            if with_segments and not turns[i]:
                count = segments_near(statics.index, x - reach, y - reach, x + reach, y + reach, near)
                for c in range(count):
                    if not beyond_segment(segments, near[c], x, y, reach):
                        turns[i] = True
                        break
            if with_map and not turns[i] and has_map(statics.map):
                turns[i] = map_sample(statics.map, x, y)[0] <= reach + statics.map.cell
        return turns
    return reach_statics


@inlined
def _travel(bodies, dt, i):
    """How far from its centre body i's bounding circle can reach within the step."""
    v, a = bodies.velocities, bodies.accelerations
    return bodies.radii[i] + (length(v[i, 0], v[i, 1]) + 0.5 * length(a[i, 0], a[i, 1]) * dt) * dt


def map_phase(bodies, statics, start, held, dt, log, now, frame_collisions):
    """Every body's move this step of dt (from start (n, 2)) against the collision map and the
    box walls together (compiled code only; response/map.py): bounces off the map are counted
    with the segments' (frame_collisions[SEGMENT]) and logged as MAP events, those off the walls
    as WALL events; a body resting or sliding on the map is not bounced. A body the contact
    solver held against the map (held (n, 5), HELD_BY_MAP) slides on it, its move still marched
    (glide_past_map), so that no step ends beyond a painted wall. Returns the log."""
    raise NotImplementedError("map_phase is called from compiled code")


def keep_start(field, start, positions):
    """With a map, copy positions into start (n, 2): the map marches each step's move from there."""
    raise NotImplementedError("keep_start is called from compiled code")


def settle_in_map(field, positions, radii):
    """With a map, push every body out of it (positions only); returns whether there was one."""
    raise NotImplementedError("settle_in_map is called from compiled code")


@overload(segment_phase)
def _segment_phase(bodies, statics, scratch, log, now, frame_collisions):
    if _lacks(statics, "index"):
        return lambda bodies, statics, scratch, log, now, frame_collisions: log

    def bounce_off_segments(bodies, statics, scratch, log, now, frame_collisions):
        b, s = bodies, statics
        if s.segments.shape[0] == 0:
            return log
        found, count = segment_contacts(b.positions, b.radii, s.segments, s.index, scratch[0], scratch[1], MARGIN)
        log = with_room(log, count)
        for c in range(count):
            i, k = found[c, 0], found[c, 1]
            if b.shapes[i] != CIRCLE:
                continue   # a polygon meets segments through the contact solver (response/rows.segment_manifolds)
            scratch[3][i, NEAR_SEGMENT] = True
            if scratch[3][i, HELD_BY_SEGMENT]:
                put_on_segment(b.positions, b.radii, s.segments, i, k)
                continue   # held there by the solver: rounding into the segment is not a bounce
            if circle_segment(b.positions, b.radii, i, s.segments, k)[2] < 0.0:
                continue   # near, not touching: nothing to bounce
            impulse, x, y = bounce_off_segment(b.positions, b.velocities, b.accelerations, b.radii, b.masses,
                                               s.segments, i, k, s.restitution)
            if impulse > 0.0:
                append(log, now, SEGMENT, i, k, impulse, x, y)
                frame_collisions[SEGMENT] += 1
        return log
    return bounce_off_segments


@overload(circle_segment_rows)
def _circle_segment_rows(bodies, statics, margin, in_pair, held, found, k, asleep):
    if _lacks(statics, "index"):
        return lambda bodies, statics, margin, in_pair, held, found, k, asleep: (found, k)

    def held_by_segments(bodies, statics, margin, in_pair, held, found, k, asleep):
        b, s = bodies, statics
        near = np.empty(max(s.segments.shape[0], 1), np.int64)
        for i in range(b.positions.shape[0]):
            if b.shapes[i] != CIRCLE or asleep[i]:
                continue
            v = b.velocities
            slow = v[i, 0] * v[i, 0] + v[i, 1] * v[i, 1] <= s.rest_speed * s.rest_speed
            if not (in_pair[i] or slow or held[i, NEAR_SEGMENT]):
                continue
            reach = b.radii[i] + margin[i]
            x, y = b.positions[i, 0], b.positions[i, 1]
            count = segments_near(s.index, x - reach, y - reach, x + reach, y + reach, near)
            found = grown(found, k + count, k)
            k = circle_segment_manifolds(b, margin, s.segments, near, count, i, s.rest_speed, in_pair, found, k)
        return found, k
    return held_by_segments


@overload(polygon_segment_rows)
def _polygon_segment_rows(bodies, statics, vertices, margin, found, k, asleep):
    if _lacks(statics, "index") or _lacks(statics, "volumes"):
        return lambda bodies, statics, vertices, margin, found, k, asleep: (found, k)

    def polygons_near_segments(bodies, statics, vertices, margin, found, k, asleep):
        near = near_segments(bodies, margin, statics.segments)
        if near == 0:
            return found, k
        found = grown(found, k + near, k)
        return found, segment_manifolds(bodies, vertices, margin, statics.segments, found, k, statics.volumes, asleep)
    return polygons_near_segments


@kernel
def map_number(segments):
    """The collision map's number among the statics a contact row names (rows.wall): after the
    box walls and the segments (m, 4)."""
    return N_WALLS + segments.shape[0]


@kernel
def static_kind(wall, the_map):
    """What a row's static number (rows.wall) names: WALL (a side), SEGMENT (N_WALLS + its
    number) or MAP (the_map, map_number's)."""
    return WALL if wall < N_WALLS else MAP if wall == the_map else SEGMENT


@overload(circle_map_rows)
def _circle_map_rows(bodies, statics, margin, in_pair, found, k, asleep):
    if _lacks(statics, "map"):
        return lambda bodies, statics, margin, in_pair, found, k, asleep: (found, k)

    def held_by_map(bodies, statics, margin, in_pair, found, k, asleep):
        b, s = bodies, statics
        if not has_map(s.map):
            return found, k
        found = grown(found, k + b.positions.shape[0], k)
        the_map = map_number(s.segments)
        for i in range(b.positions.shape[0]):
            if b.shapes[i] == CIRCLE and not asleep[i]:
                k = circle_map_manifold(b, margin, s.map, the_map, i, s.rest_speed, in_pair, found, k)
        return found, k
    return held_by_map


@overload(map_phase)
def _map_phase(bodies, statics, start, held, dt, log, now, frame_collisions):
    if _lacks(statics, "map"):
        return lambda bodies, statics, start, held, dt, log, now, frame_collisions: log

    def bounce_off(bodies, statics, start, held, dt, log, now, frame_collisions):
        b = bodies
        if not has_map(statics.map):
            return log
        s = statics
        walls = np.zeros(N_WALLS)   # each wall side's first impulse off body i
        for i in range(b.positions.shape[0]):
            log = with_room(log, 1 + N_WALLS)
            walls[:] = 0.0
            if held[i, HELD_BY_MAP]:   # held there by the solver: rounding into the map is not a bounce
                impulse, x, y, bounces, wall_bounces = glide_past_map(
                    s.map, s.box, held, start, b.positions, b.velocities, b.accelerations, b.radii, b.masses,
                    s.restitution, s.rest_speed, dt, i, walls)
            else:
                impulse, x, y, bounces, wall_bounces = bounce_off_map(
                    s.map, s.box, held, start, b.positions, b.velocities, b.accelerations, b.radii, b.masses,
                    s.restitution, s.rest_speed, dt, i, walls)
            if bounces > 0:
                append(log, now, MAP, i, -1, impulse, x, y)
                frame_collisions[SEGMENT] += bounces
            for side in range(N_WALLS):
                if walls[side] > 0.0:
                    _log_wall(log, now, b.positions, s.box, i, side // 2, np.int64(side % 2), walls[side])
            frame_collisions[WALL] += wall_bounces
        return log
    return bounce_off


@overload(keep_start)
def _keep_start(field, start, positions):
    if isinstance(field, types.NoneType):
        return lambda field, start, positions: None

    def copy(field, start, positions):
        if has_map(field):
            copy_rows(positions, start, positions.shape[0])   # (arrays.py: not a slice assignment)
    return copy


@overload(settle_in_map)
def _settle_in_map(field, positions, radii):
    if isinstance(field, types.NoneType):
        return lambda field, positions, radii: False

    def push_all_out(field, positions, radii):
        if not has_map(field):
            return False
        for i in range(positions.shape[0]):
            push_out(field, positions, radii[i], i)
        return True
    return push_all_out


@compiled
def statics_scratch(n, m):
    """Buffers for statics_phase: segment contacts (room for one a body; grown when a step has
    more), near segments (m,), the positions (n, 2) at the start of the step (the map
    marches each step's move from there), and held (n, 5) bool: the axes on which the contact
    solver held a body against a wall this step, and whether it held it against a segment
    (HELD_BY_SEGMENT) or the map (HELD_BY_MAP): it is put back there, not bounced; and whether
    it is near a segment after the statics phase (NEAR_SEGMENT: circle_segment_rows)."""
    return (np.empty((n + 16, 2), np.int64), np.empty(max(m, 1), np.int64), np.empty((n, 2)),
            np.zeros((n, 5), np.bool_))


@kernel
def mark_held(rows, count, held, the_map):
    """held (n, 5): the axes on which a wall row held each body this step, and whether a
    segment's row (HELD_BY_SEGMENT) or the map's (the static numbered the_map: HELD_BY_MAP) held
    it; NEAR_SEGMENT cleared, for the segment phase to set."""
    held[:] = False
    for r in range(count):
        if rows.j[r] < 0 and rows.impulse[r] > 0.0:
            wall, kind = rows.wall[r], static_kind(rows.wall[r], the_map)
            held[rows.i[r], wall // 2 if kind == WALL else HELD_BY_MAP if kind == MAP else HELD_BY_SEGMENT] = True


@compiled
def statics_phase(bodies, statics, scratch, dt, log, now, frame_collisions):
    """Segments, then walls, in place; collisions added to frame_collisions (3,: wall, pair,
    segment) and log. scratch from statics_scratch. Returns the log."""
    b, s = bodies, statics
    log = segment_phase(b, s, scratch, log, now, frame_collisions)
    log = map_phase(b, s, scratch[2], scratch[3], dt, log, now, frame_collisions)
    log = with_room(log, 4 * b.positions.shape[0])  # at most one event per body and wall
    for i in range(b.positions.shape[0]):
        if b.shapes[i] != CIRCLE:
            continue   # a polygon meets the walls through the contact solver only
        for axis in range(2):
            low, high = centre_range(s.box, axis, b.radii[i])
            if low <= b.positions[i, axis] <= high:
                continue  # the extreme points are inside: no wall touched on this axis
            if scratch[3][i, axis]:
                b.positions[i, axis] = min(max(b.positions[i, axis], low), high)
                continue  # held there by the solver: rounding past the wall is not a bounce
            low_bounces, high_bounces, low_impulse, high_impulse = bounce_between_walls(
                b.positions, b.velocities, b.accelerations, b.radii, b.masses, s.box, s.restitution, i, axis)
            if low_bounces > 0:
                _log_wall(log, now, b.positions, s.box, i, axis, LOW_SIDE, low_impulse)
            if high_bounces > 0:
                _log_wall(log, now, b.positions, s.box, i, axis, HIGH_SIDE, high_impulse)
            frame_collisions[WALL] += low_bounces + high_bounces
    return log


@kernel
def _log_wall(log, now, positions, box, i, axis, side, impulse):
    """Log body i's bounce off wall 2·axis + side, at the wall beside the body."""
    on_wall, along = box[axis + 2 * side], positions[i, 1 - axis]
    x, y = (on_wall, along) if axis == 0 else (along, on_wall)
    append(log, now, WALL, i, 2 * axis + side, impulse, x, y)
