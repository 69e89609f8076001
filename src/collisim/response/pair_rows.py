"""Contact rows between bodies: the pairs whose shapes are within their speculative margins
(response/rows.py has the whole rule and the record each manifold makes), found from the
state at the start of the step, and the near misses a sweep lets pass.

A speculative pair (still apart) gives rows only if the bodies' motion in the step can bring
their shapes together at all (_may_meet); where the sweep's straight lines may not hold (a body
that can reach a box wall, a segment or the map in the step, a body another pair's rows may
turn) the pair keeps its rows.
"""
import numpy as np

from ..core.compiling import compiled, inlined, kernel
from ..core.geometry.toi import time_to_pair
from ..core.geometry.vector import length
from ..core.kinds import CIRCLE
from ..narrowphase.circles import circles_touch
from ..narrowphase.manifold import body_pair_manifold, body_pair_swept_gap
from .rows import APART, MEET_TOLERANCE, SLOP, reaches, record_manifold


@kernel
def _circles_at_contact(positions, velocities, radii, i, j, dt, m):
    """Two circles still apart that touch within the step: their manifold where they meet, with
    the normal at the time of contact t (uniform gravity cancels between them) and the gap closed
    until then along it, -(v_j - v_i)·n·t. Taking the normal at the start of the step instead
    would turn an oblique impact by the distance the bodies slide past each other before they
    meet. Manifold m as it is if they do not touch within the step."""
    dx, dy = positions[j, 0] - positions[i, 0], positions[j, 1] - positions[i, 1]
    dvx, dvy = velocities[j, 0] - velocities[i, 0], velocities[j, 1] - velocities[i, 1]
    reach = radii[i] + radii[j]
    t = time_to_pair(dx, dy, dvx, dvy, reach, dt)
    if not t < np.inf:
        return m
    nx, ny = (dx + dvx * t) / reach, (dy + dvy * t) / reach
    gap = -(dvx * nx + dvy * ny) * t
    x, y = positions[i, 0] + velocities[i, 0] * t, positions[i, 1] + velocities[i, 1] * t
    return nx, ny, 1, -gap, x + radii[i] * nx, y + radii[i] * ny, 0.0, 0.0, 0.0


@kernel
def _circles_apart(positions, radii, i, j, reach):
    """Are the bounding circles of bodies i and j farther apart than they can close (reach)?"""
    dx, dy = positions[j, 0] - positions[i, 0], positions[j, 1] - positions[i, 1]
    return dx * dx + dy * dy > (APART * (radii[i] + radii[j] + reach)) ** 2


@compiled
def pair_reaches(bodies, vertices, margin, i, j, polygons):
    """Does pair_manifolds look at bodies i and j and find a point within the sum of their
    margins (taken where they are, before a pair of circles is met at its time of contact)?"""
    b, reach = bodies, margin[i] + margin[j]
    if _circles_apart(b.positions, b.radii, i, j, reach):
        return False
    return reaches(body_pair_manifold(polygons, b.shapes, b.positions, b.radii, vertices, b.vertex_start, i, j,
                                       reach), reach)


@compiled
def pair_manifolds(bodies, vertices, margin, dt, pairs, found, k, in_pair, touching, polygons, asleep, turns):
    """Record after found[:k] the manifolds of pairs (p, 2) (canonical order, i < j) with a point
    closer than the sum of their margins; in_pair (n,) marks their bodies, and touching (p,)
    says of each pair whether its shapes touch now (the exact level of the bounding-volume
    funnel, narrowphase/hierarchy.py, read from the manifold the step needs anyway: circles by
    circles_touch, a polygon by its manifold's depth >= 0). Returns the new record count.
    polygons: core/kinds.shapes_flag of the world, by which a world of circles compiles no polygon
    path and a world without capsules no capsule path (manifold.body_pair_manifold). asleep (n,) bool: a pair
    of sleepers (engine/islands.py) has no manifold (its touching is left False). turns (n,) bool:
    which bodies a static may turn within the step (engine/statics_paths.may_turn), for _may_meet."""
    shapes, positions, radii = bodies.shapes, bodies.positions, bodies.radii
    passing, count = np.empty(pairs.shape[0], np.int64), 0   # speculative pairs the sweep lets pass
    for c in range(pairs.shape[0]):
        i, j = pairs[c, 0], pairs[c, 1]
        touching[c] = False
        reach = margin[i] + margin[j]
        if _circles_apart(positions, radii, i, j, reach):
            continue   # their bounding circles are farther apart than they can close
        if asleep[i] and asleep[j]:
            continue   # no contact (engine/islands.py finds their touching)
        m = _pair_manifold(bodies, vertices, polygons, i, j, reach, dt)
        circles = shapes[i] == CIRCLE and shapes[j] == CIRCLE
        touching[c] = circles_touch(positions, radii, i, j) if circles else m[2] > 0 and m[3] >= 0.0
        if not reaches(m, reach):
            continue
        if m[3] >= 0.0 or _may_meet(bodies, vertices, i, j, dt, -m[3], polygons, turns):
            k = record_manifold(found, k, i, j, -1, reach, SLOP * min(radii[i], radii[j]), m)
            in_pair[i] = in_pair[j] = True
        else:
            passing[count] = c
            count += 1
    return _held_after_all(bodies, vertices, margin, dt, pairs, passing, count, found, k, in_pair, polygons)


@inlined
def _pair_manifold(bodies, vertices, polygons, i, j, reach, dt):
    """The manifold of bodies i and j within reach; two circles apart, at their time of contact."""
    b = bodies
    m = body_pair_manifold(polygons, b.shapes, b.positions, b.radii, vertices, b.vertex_start, i, j, reach)
    if b.shapes[i] == CIRCLE and b.shapes[j] == CIRCLE and m[2] == 1 and m[3] < 0.0:
        m = _circles_at_contact(b.positions, b.velocities, b.radii, i, j, dt, m)
    return m


@compiled
def _held_after_all(bodies, vertices, margin, dt, pairs, passing, count, found, k, in_pair, polygons):
    """Record the pairs the sweep let pass (pairs[passing[:count]]) of which a body is in another
    pair's rows after all, until none is: the solve may turn that body, and the sweep's straight
    lines no longer hold (a ball another ball struck was turned into a third it had been let pass,
    and sank half its radius into it). Returns the new record count."""
    changed = True
    while changed:
        changed = False
        for e in range(count):
            c = passing[e]
            if c < 0:
                continue
            i, j = pairs[c, 0], pairs[c, 1]
            if in_pair[i] or in_pair[j]:
                reach = margin[i] + margin[j]
                m = _pair_manifold(bodies, vertices, polygons, i, j, reach, dt)
                k = record_manifold(found, k, i, j, -1, reach, SLOP * min(bodies.radii[i], bodies.radii[j]), m)
                in_pair[i] = in_pair[j] = True
                passing[e], changed = -1, True
    return k


@inlined
def _may_meet(bodies, vertices, i, j, dt, gap, polygons, turns):
    """Can bodies i and j, `gap` apart where the step starts, meet within it? A speculative
    pair that cannot gets no rows: its normal joins the closest features where the step starts,
    and along it a corner sliding past a corner (a ball past a box's corner 0.03 above it at 17
    units/s) closes faster than its gap though the two never meet; its rows pushed both bodies
    and logged a collision (a ghost collision). They may meet if their shapes, the second moved
    along the pair's mean relative velocity (uniform gravity cancels), come within the slack of
    what the sweep leaves out: a polygon's turning (|ω|·its radius·dt moves any of its points no
    farther), and each body's pull over the step (a body held by the floor loses its fall while
    the one on it does not: a resting pile's gaps close by that much; narrowphase/sweep.py).

    The sweep moves both bodies in straight lines, so it holds only where nothing else turns them
    within the step: a pair of which a body may reach a box wall, a segment or the map in the
    step (turns) keeps its rows as before. A ball bounced off the floor in mid-step turned into
    the body the sweep had let it pass, and sank deep into it (particles_250)."""
    b = bodies
    if turns[i] or turns[j]:
        return True
    w, a, r = b.angular_velocities, b.accelerations, b.radii
    spin = (abs(w[i]) * r[i] if b.shapes[i] != CIRCLE else 0.0) + (abs(w[j]) * r[j] if b.shapes[j] != CIRCLE else 0.0)
    pull = length(a[i, 0], a[i, 1]) + length(a[j, 0], a[j, 1])
    slack = spin * dt + pull * dt * dt + MEET_TOLERANCE * (r[i] + r[j])
    if gap <= slack:
        return True
    half = 0.5 * dt
    dx = (b.velocities[j, 0] + half * a[j, 0] - b.velocities[i, 0] - half * a[i, 0]) * dt
    dy = (b.velocities[j, 1] + half * a[j, 1] - b.velocities[i, 1] - half * a[i, 1]) * dt
    return body_pair_swept_gap(polygons, b.shapes, b.positions, b.radii, vertices, b.vertex_start, i, j, dx,
                               dy) <= slack
