"""The contact rows of one step: every contact point the solver (response/solver.py) must hold.

Rows are made from the state at the *start* of the step, before anything moves:

* pairs of bodies whose gap is less than what the two could close in the step (their
  speculative margins, `margins`): a pair still apart gives *speculative* rows, which only act
  if the step would close the gap past zero (so an impact stops the bodies where they meet
  instead of sinking one into the other, and a ball resting on a ball is held by it) — and only
  if the bodies' motion in the step can bring their shapes together at all (response/pair_rows.py:
  a body sliding past a corner gets none);
* a polygon and a segment within its margin (segment_manifolds);
* a body and a box wall: a polygon within reach of the wall always — its reach there is how far
  it can move in the step, not capped at its radius as a margin is, since a box wall may not be
  passed at any speed (a box of 0.01 falling at 9.8 units/s, 33 times its size a frame at 30 fps,
  went through the floor and came to rest below it); a circle when it is
  within its margin and either meets the wall slower than the rest speed (it rests there) or
  touches another body this step (a pile must be held by the floor in the same solve as by its
  neighbours). A lone circle's fast impact is left to the wall bounce (response/statics.py),
  which reflects the overshoot exactly;
* a circle and a segment, or the collision map, by the same rule as a circle and a wall
  (circle_segment_manifolds, circle_map_manifold). Left to the bounce alone, a pile on a
  segment or a map sank into itself: each step the bounce put the bottom circles back out,
  into the circles the solver had just pushed them away from (two circles of a pile
  coincided within seconds).

The contact phases first collect the *manifolds* of these contacts (narrowphase/manifold.py),
one record each in a scratch array (`new_found`: who meets whom, how far a point may be and
still count, the slop), then `rows_from` makes one row per point of each — two for a face on a
face. (Collected first, the rows are written in one loop that reads every array once: a helper
handed the Rows tuple costs a copy of its sixteen references per call, more than its work.)
Each row has a unit normal from body i toward body j (into the wall), its point, the point's arm from
each centre, the gap along the normal (negative for an overlap) and the effective masses along
the normal and the tangent. Rows are in canonical order — pairs in (i, j) order, then walls in
(body, wall) order, points in manifold order — so the same input gives the same bytes whichever
broad phase found the pairs.
"""
from collections import namedtuple

import numpy as np

from ..core.compiling import compiled, constructor, inlined, kernel
from ..core.geometry.box import wall_geometry
from ..core.geometry.vector import length
from ..core.kinds import CIRCLE, N_WALLS
from ..narrowphase.manifold import body_segment_manifold, body_wall_manifold
from ..narrowphase.statics import circle_segment
from ..statics.map_field import map_contact, map_sample

SLOP = 0.005   # of the smaller radius: an overlap the solver tolerates between bodies (solver.py)
MARGIN = 0.01  # of the radius: every body's smallest speculative margin (a resting pile that falls
               # ½·g·dt² between two steps must not lose its rows to rounding)

Rows = namedtuple("Rows", ["i", "j", "wall", "feature", "partner", "normal", "point", "lever", "gap",
                           "mass", "mass_t", "hit", "impulse", "friction", "pseudo", "slop", "arrives"])
Rows.__doc__ = """Contact rows, each (k,) or (k, 2): i, j the bodies (j = -1 for a row of a static: `wall` is the
box wall's side, or N_WALLS + k for segment k; else -1); feature the point's number in its
manifold (0 or 1); partner the row of the manifold's other point, or -1; normal unit, from i
toward j (into the wall); point where they meet; lever (k, 4) the turning lever of the point
about each centre, arm × n and arm × t for body i then body j (0 for a wall): a unit impulse
along n turns body i by -lever[0]/I_i, and the point's velocity along n includes ω_i·lever[0];
gap along the normal at the start of the step (< 0: overlapping); mass, mass_t the effective
masses along the normal and the tangent (-n_y, n_x); hit the impact impulse, impulse and
friction the accumulated contact impulses along the normal and the tangent, pseudo the position
impulse (set by the solver); slop the overlap the row tolerates; arrives (k,) bool: an impact
the solve completes, a perfectly inelastic contact with a static still apart (solver.collide)."""


@inlined
def was_impact(rows, r):
    """Did row r meet as an impact this step (an impulse in hit, or an arrival: solver.collide)?
    Impacts are logged as collisions and kept out of the next step's warm start."""
    return rows.hit[r] > 0.0 or rows.arrives[r]


@constructor
def new_rows(capacity):
    k = max(capacity, 1)
    ints, reals, pairs = (lambda: np.empty(k, np.int64)), (lambda: np.zeros(k)), (lambda: np.empty((k, 2)))
    return Rows(ints(), ints(), ints(), ints(), ints(), pairs(), pairs(), np.zeros((k, 4)), reals(), reals(),
                reals(), reals(), reals(), reals(), reals(), reals(), np.zeros(k, np.bool_))


@kernel
def margins(velocities, angular_velocities, accelerations, radii, dt, out):
    """Each body's speculative margin (n,): how far any of its points can move in a step of dt,
    capped at its radius (a faster body may still tunnel: that is the discrete method's known
    limit), and at least MARGIN of its radius."""
    for i in range(radii.shape[0]):
        out[i] = margin_of(velocities, angular_velocities, accelerations, radii, dt, i)


@kernel
def margin_of(velocities, angular_velocities, accelerations, radii, dt, i):
    """Body i's speculative margin (margins)."""
    return max(min(_travel(velocities, angular_velocities, accelerations, radii, dt, i), radii[i]), MARGIN * radii[i])


@kernel
def _travel(velocities, angular_velocities, accelerations, radii, dt, i):
    """How far any point of body i can move in a step of dt."""
    speed = length(velocities[i, 0], velocities[i, 1]) + abs(angular_velocities[i]) * radii[i]
    pull = length(accelerations[i, 0], accelerations[i, 1])
    return speed * dt + pull * dt * dt


# a found manifold's record (new_found): the bodies (j = -1 for a static, `wall` naming it), the
# distance within which its points count, their slop, then the manifold itself (manifold.py):
# nx, ny, point count, then depth, x, y of each point
F_I, F_J, F_WALL, F_REACH, F_SLOP, F_MANIFOLD = 0, 1, 2, 3, 4, 5
FOUND = F_MANIFOLD + 9
APART = 1.0 + 1e-9   # bounding circles this much farther than a reach are apart: no exact test
MEET_TOLERANCE = 1e-9   # of the two radii: a sweep that comes this close meets (rounding)


@constructor
def new_found(capacity):
    """Room for `capacity` manifold records (capacity, FOUND)."""
    return np.empty((max(capacity, 1), FOUND))


@kernel
def record_manifold(found, k, i, j, wall, reach, slop, m):
    """Record k: manifold m of bodies i and j (or of body i and a static `wall`)."""
    record = found[k]
    record[F_I], record[F_J], record[F_WALL], record[F_REACH], record[F_SLOP] = i, j, wall, reach, slop
    nx, ny, count, d0, px0, py0, d1, px1, py1 = m
    manifold = record[F_MANIFOLD:]
    manifold[0], manifold[1], manifold[2], manifold[3], manifold[4] = nx, ny, count, d0, px0
    manifold[5], manifold[6], manifold[7], manifold[8] = py0, d1, px1, py1
    return k + 1


@kernel
def reaches(m, reach):
    """Has manifold m a point closer than reach?"""
    return m[2] > 0 and -m[3] < reach


@kernel
def wall_manifolds(bodies, vertices, margin, dt, box, rest_speed, in_pair, found, k, polygons, asleep):
    """Record after found[:k] the manifolds of bodies held by a box wall (see the module's rule).
    in_pair (n,) bool: bodies in a pair's manifold; polygons as for pair_manifolds. Returns the
    new record count. No overlap of a wall is tolerated: a wall cannot give way. Sleepers (asleep
    (n,) bool) have none: they rest on their walls as they fell asleep (engine/islands.py)."""
    shapes, positions, velocities, radii, start = (bodies.shapes, bodies.positions, bodies.velocities,
                                                   bodies.radii, bodies.vertex_start)
    for i in range(positions.shape[0]):
        if asleep[i]:
            continue
        polygon = shapes[i] != CIRCLE
        # a polygon's reach: the whole step's travel (the module)
        reach = max(margin[i], _travel(velocities, bodies.angular_velocities, bodies.accelerations, radii, dt, i)
                    ) if polygon else margin[i]
        for wall in range(4):
            axis, bound, inward = wall_geometry(box, wall, radii[i])
            gap = (positions[i, axis] - bound) * inward   # of the body's bounding circle
            if polygon:
                if gap > APART * reach:
                    continue
                m = body_wall_manifold(polygons, shapes, radii, vertices, start, i, box, wall, reach)
                if reaches(m, reach):
                    k = record_manifold(found, k, i, -1, wall, reach, 0.0, m)
                continue
            if gap >= margin[i]:
                continue
            if -velocities[i, axis] * inward > rest_speed and not in_pair[i]:
                continue   # a lone fast impact: the exact wall bounce takes it
            nx, ny = (-inward, 0.0) if axis == 0 else (0.0, -inward)
            midway = radii[i] + 0.5 * gap   # between the circle and the wall
            m = (nx, ny, 1, -gap, positions[i, 0] + midway * nx, positions[i, 1] + midway * ny, 0.0, 0.0, 0.0)
            k = record_manifold(found, k, i, -1, wall, margin[i], 0.0, m)
    return k


@kernel
def circle_segment_manifolds(bodies, margin, segments, near, count, i, rest_speed, in_pair, found, k):
    """Record after found[:k] the manifolds of circle i with the segments near[:count] that hold
    it (_held_by_static): j = -1, wall = N_WALLS + the segment's number. Returns the new record
    count (the caller makes the room)."""
    for c in range(count):
        s = near[c]
        nx, ny, depth, _, _ = circle_segment(bodies.positions, bodies.radii, i, segments, s)   # segment -> centre
        k = _held_by_static(bodies, margin, i, nx, ny, -depth, N_WALLS + s, rest_speed, in_pair, found, k)
    return k


@kernel
def circle_map_manifold(bodies, margin, field, static, i, rest_speed, in_pair, found, k):
    """Record as found[k] the manifold of circle i with the collision map (field) if it holds it
    (_held_by_static): its gap is the map's distance at the centre less the radius, its normal
    the map's; j = -1, wall = `static` (the map's number: N_WALLS + the number of segments).
    Returns the new record count (the caller makes the room). A body meeting the map no faster
    than the rest speed (resting, sliding or rolling on it) reads it across its width
    (map_contact: a staircase as the slope it draws); an impact, in a pile, reads it at the
    centre, whose normal points at the solid it hits, a sharp point included."""
    x, y, v = bodies.positions[i, 0], bodies.positions[i, 1], bodies.velocities
    d, nx, ny = map_contact(field, x, y, bodies.radii[i])   # out of the map
    if -(v[i, 0] * nx + v[i, 1] * ny) > rest_speed:
        d, nx, ny = map_sample(field, x, y)
    if nx == 0.0 and ny == 0.0:
        return k   # no normal (deep in the solid, or on a ridge): the map's push-out takes it
    return _held_by_static(bodies, margin, i, nx, ny, d - bodies.radii[i], static, rest_speed, in_pair, found, k)


@inlined
def _held_by_static(bodies, margin, i, nx, ny, gap, static, rest_speed, in_pair, found, k):
    """Record circle i's manifold with a static at `gap` along (nx, ny) (from the static to the
    centre) if the static holds it, by the rule of a circle and a wall (wall_manifolds): within
    its margin, and either meeting it slower than the rest speed (resting, rolling or sliding
    along it) or in a pair's manifold; a lone fast impact is left to the static's exact bounce
    (response/statics.py, response/map.py). Returns the new count."""
    positions, velocities = bodies.positions, bodies.velocities
    if gap >= margin[i]:
        return k
    if -(velocities[i, 0] * nx + velocities[i, 1] * ny) > rest_speed and not in_pair[i]:
        return k
    reach = bodies.radii[i] + 0.5 * gap   # midway between the circle and the static
    m = (-nx, -ny, 1, -gap, positions[i, 0] - reach * nx, positions[i, 1] - reach * ny, 0.0, 0.0, 0.0)
    return record_manifold(found, k, i, -1, static, margin[i], 0.0, m)


@compiled
def segment_manifolds(bodies, vertices, margin, segments, found, k, polygons, asleep):
    """Record after found[:k] the manifolds of polygons within their margin of a segment (m, 4):
    j = -1, wall = N_WALLS + the segment's number; polygons as for pair_manifolds. Returns the
    new record count. A segment, like a wall, cannot give way: no overlap is tolerated. Sleepers
    (asleep (n,) bool) have none, as for wall_manifolds."""
    shapes, positions, radii, start = bodies.shapes, bodies.positions, bodies.radii, bodies.vertex_start
    for i in range(positions.shape[0]):
        if shapes[i] == CIRCLE or asleep[i]:
            continue
        x, y, reach = positions[i, 0], positions[i, 1], radii[i] + margin[i]
        for s in range(segments.shape[0]):
            if beyond_segment(segments, s, x, y, reach):
                continue
            m = body_segment_manifold(polygons, shapes, radii, vertices, start, i, segments, s, margin[i])
            if reaches(m, margin[i]):
                k = record_manifold(found, k, i, -1, N_WALLS + s, margin[i], 0.0, m)
    return k


@kernel
def _levers(ax, ay, nx, ny):
    """A point's turning levers about a centre, from its arm (ax, ay): arm × n and arm × t."""
    return ax * ny - ay * nx, ax * nx + ay * ny


@kernel
def _effective_mass(m_i, inertia_i, lever_i, m_j, inertia_j, lever_j, j):
    """1 / (the velocity change at a point along a direction per unit impulse along it)."""
    k = 1.0 / m_i + lever_i * lever_i / inertia_i
    if j >= 0:
        k += 1.0 / m_j + lever_j * lever_j / inertia_j
    return 1.0 / k


@kernel
def rows_from(found, k, bodies, rows):
    """The rows of found[:k]'s manifolds: one a point closer than its record's reach, in record
    order, then point order. A row of two circles, or of a circle and a wall, meets on their line
    of centres, so a push along it turns neither (levers exactly 0: the product of the rounded
    arm with the normal would leave a residue that sets circles spinning), and friction turns
    each by its radius. Returns the number of rows."""
    shapes, positions, radii, masses, inertias = (bodies.shapes, bodies.positions, bodies.radii, bodies.masses,
                                                  bodies.inertias)
    I, J, W, F, P, N, X, L = rows.i, rows.j, rows.wall, rows.feature, rows.partner, rows.normal, rows.point, rows.lever
    gap, slop, mass, mass_t = rows.gap, rows.slop, rows.mass, rows.mass_t
    count = 0
    for f in range(k):
        i, j, wall = int(found[f, F_I]), int(found[f, F_J]), int(found[f, F_WALL])
        nx, ny, points = found[f, F_MANIFOLD], found[f, F_MANIFOLD + 1], int(found[f, F_MANIFOLD + 2])
        circles = shapes[i] == CIRCLE and (j < 0 or shapes[j] == CIRCLE)
        m_j, inertia_j = (masses[j], inertias[j]) if j >= 0 else (1.0, 1.0)
        first = count
        for point in range(points):
            depth, px, py = found[f, F_MANIFOLD + 3 + 3 * point], found[f, F_MANIFOLD + 4 + 3 * point], \
                found[f, F_MANIFOLD + 5 + 3 * point]
            if not -depth < found[f, F_REACH]:
                continue
            I[count], J[count], W[count], F[count], P[count] = i, j, wall, point, -1
            N[count, 0], N[count, 1], X[count, 0], X[count, 1] = nx, ny, px, py
            gap[count], slop[count] = -depth, found[f, F_SLOP]
            if circles:
                l0, l1, l2, l3 = 0.0, radii[i], 0.0, (-radii[j] if j >= 0 else -0.0)
            else:
                l0, l1 = _levers(px - positions[i, 0], py - positions[i, 1], nx, ny)
                l2, l3 = _levers(px - positions[j, 0], py - positions[j, 1], nx, ny) if j >= 0 else (0.0, 0.0)
            L[count, 0], L[count, 1], L[count, 2], L[count, 3] = l0, l1, l2, l3
            mass[count] = _effective_mass(masses[i], inertias[i], l0, m_j, inertia_j, l2, j)
            mass_t[count] = _effective_mass(masses[i], inertias[i], l1, m_j, inertia_j, l3, j)
            count += 1
        if count - first == 2:
            P[first], P[first + 1] = first + 1, first
    return count


@kernel
def beyond_segment(segments, k, x, y, reach):
    """Is segment k farther than reach from (x, y)? (Its box, grown by reach, misses the point.)"""
    x0, y0, x1, y1 = segments[k, 0], segments[k, 1], segments[k, 2], segments[k, 3]
    return (x < min(x0, x1) - reach or x > max(x0, x1) + reach or y < min(y0, y1) - reach
            or y > max(y0, y1) + reach)


@kernel
def near_segments(bodies, margin, segments):
    """How many (polygon, segment) pairs are near enough for segment_manifolds to look at."""
    b = bodies
    near = 0
    if segments.shape[0] == 0:
        return 0
    for i in range(b.positions.shape[0]):
        if b.shapes[i] != CIRCLE:
            for k in range(segments.shape[0]):
                near += not beyond_segment(segments, k, b.positions[i, 0], b.positions[i, 1], b.radii[i] + margin[i])
    return near
