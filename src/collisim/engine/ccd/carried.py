"""The weight of sleeping bodies, carried down through the pile to the walls and segments.

A sleeping body (sleep.py) is frozen and has no events, but it still weighs: in a settled
pile the floor carries every body, not only the bottom layer resting on it. So each sleeper
keeps a load (Supports.load, an impulse vector): its weight times the time since it was last
carried, what the bodies resting on it passed to it, and the hits it took without waking.

At every frame time the loads go down the pile, from the highest sleeper to the lowest. Each
sleeper splits its load between the two of its supports whose normals lie nearest the load's
direction on either side of it — the walls, segments and lower sleeping bodies it touches
(within sleep.SLEEP_GAP of its radius) — by the same two-support statics as a body wedged on
two walls (support.py): N_a a + N_b b = -load. A wall or a segment logs what it gets as a
kinds.SUPPORT event of the sleeper touching it; a sleeping body adds the reaction to its own
load, to pass on in turn. A body that wakes hands what it owes to its supports the same way,
at that instant, before it moves. So a still pile gives the floor its whole weight, m·g·dt
per body and frame, and its pressure on the side walls where it leans on them.

Exact wherever each sleeper's load lies between two of its supports, as in a settled pile.
A load that no two supports enclose (a sleeper frozen leaning on a body still awake) goes to
the support nearest its direction, along that support's normal; a sleeper with no sleeping
support keeps its load until it has one, or wakes.
"""
import math

import numpy as np
from numba import njit

from ...broadphase.cells import is_apart, reach_block
from ...geometry.box import wall_geometry
from ...geometry.segment import segment_contact
from ...model.kinds import N_WALLS, PAIR, SUPPORT
from ..eventlog import append, with_room
from .sleep import SLEEP_GAP, UPRIGHT
from .support import log_impulses

NONE = -1


@njit(cache=True, error_model="numpy")
def take_hits(supports, contacts):
    """Add to each sleeper's load the impulse of the contacts of this instant that hit it
    without waking it (resolve.py: the awake body's contact, j = -1, pushing it along n)."""
    for k in range(contacts.count[0]):
        if contacts.kind[k] == PAIR and contacts.j[k] < 0:
            sleeper = contacts.other[k]
            supports.load[sleeper, 0] += contacts.impulse[k] * contacts.nx[k]
            supports.load[sleeper, 1] += contacts.impulse[k] * contacts.ny[k]


@njit(cache=True, error_model="numpy")
def _owe_weight(bodies, env, supports, i, t):
    """Add particle i's weight since it was last carried to its load."""
    duration = t - supports.since[i]
    supports.load[i, 0] += bodies.mass[i] * env.gravity[0] * duration
    supports.load[i, 1] += bodies.mass[i] * env.gravity[1] * duration
    supports.since[i] = t


@njit(cache=True, error_model="numpy")
def _enter(log, bodies, env, supports, i, t):
    """Particle i has fallen asleep: what its own supports gave it is logged up to t, and from
    t on its weight is carried as a load."""
    log_impulses(log, bodies, env, supports, i, t)
    supports.sleeping[i] = True


@njit(cache=True, error_model="numpy")
def _nearer(angle, support, nx, ny, side, best):
    """Keep the support nearest the load's direction on one side: side +1 for angles >= 0
    (the smallest), -1 for angles <= 0 (the largest). best = (angle, support, nx, ny)."""
    if side * angle >= 0.0 and side * angle < side * best[0]:
        return angle, support, nx, ny
    return best


@njit(cache=True, error_model="numpy")
def _supports_of(bodies, grid, env, supports, i, ux, uy):
    """The supports of sleeper i nearest direction u on either side: two (angle, support,
    nx, ny), support a wall, N_WALLS + segment, or N_WALLS + segments + body (NONE: none)."""
    x, y, r = bodies.pos[i, 0], bodies.pos[i, 1], bodies.radius[i]
    left, right = (10.0, NONE, 0.0, 0.0), (-10.0, NONE, 0.0, 0.0)
    for wall in range(N_WALLS):
        axis, bound, inward = wall_geometry(env.box, wall, r)
        if abs((x, y)[axis] - bound) <= SLEEP_GAP * r:
            nx, ny = (inward, 0.0) if axis == 0 else (0.0, inward)
            angle = math.atan2(ux * ny - uy * nx, ux * nx + uy * ny)
            left, right = _nearer(angle, wall, nx, ny, 1.0, left), _nearer(angle, wall, nx, ny, -1.0, right)
    c = grid.cell[i]
    apart = is_apart(grid, i)
    first, last = (0, env.segments.shape[0]) if apart else (grid.segment_start[c], grid.segment_start[c + 1])
    for k in range(first, last):
        segment = k if apart else grid.segment_index[k]
        nx, ny, distance = segment_contact(x, y, env.segments[segment])[:3]
        if distance - r <= SLEEP_GAP * r:
            angle = math.atan2(ux * ny - uy * nx, ux * nx + uy * ny)
            support = N_WALLS + segment
            left, right = _nearer(angle, support, nx, ny, 1.0, left), _nearer(angle, support, nx, ny, -1.0, right)
    bodies_from = N_WALLS + env.segments.shape[0]
    cx_lo, cx_hi, cy_lo, cy_hi = reach_block(grid, c, grid.reach[i])
    for slot in range((cx_hi - cx_lo) * (cy_hi - cy_lo) + grid.apart.shape[0]):
        cells = (cx_hi - cx_lo) * (cy_hi - cy_lo)
        if slot < cells:
            j = grid.head[(cy_lo + slot // (cx_hi - cx_lo)) * grid.nx + cx_lo + slot % (cx_hi - cx_lo)]
        else:
            j = grid.apart[slot - cells]
        while j >= 0:
            dx, dy = x - bodies.pos[j, 0], y - bodies.pos[j, 1]
            distance = math.sqrt(dx * dx + dy * dy)
            # a sleeping body it touches, lower than it (against gravity): loads go downwards only
            if j != i and supports.sleeping[j] and distance > 0.0 and \
                    distance - r - bodies.radius[j] <= SLEEP_GAP * min(r, bodies.radius[j]) and \
                    dx * env.gravity[0] + dy * env.gravity[1] < 0.0:
                nx, ny = dx / distance, dy / distance
                angle = math.atan2(ux * ny - uy * nx, ux * nx + uy * ny)
                support = bodies_from + j
                left, right = _nearer(angle, support, nx, ny, 1.0, left), _nearer(angle, support, nx, ny, -1.0, right)
            j = grid.next[j] if slot < cells else -1
    return left, right


@njit(cache=True, error_model="numpy")
def _deliver(log, bodies, env, supports, i, t, support, nx, ny, push):
    """Support `support` pushes sleeper i along its normal n with impulse `push`: a wall or a
    segment logs it, a sleeping body takes the reaction into its load."""
    if not push > 0.0:
        return
    bodies_from = N_WALLS + env.segments.shape[0]
    if support < bodies_from:
        r = bodies.radius[i]
        append(log, t, SUPPORT, i, support, push, bodies.pos[i, 0] - r * nx, bodies.pos[i, 1] - r * ny)
    else:
        supports.load[support - bodies_from, 0] -= push * nx
        supports.load[support - bodies_from, 1] -= push * ny


@njit(cache=True, error_model="numpy")
def pass_on(log, bodies, grid, env, supports, i, t):
    """Split sleeper i's load between its supports (module docstring); its load is then 0, or
    kept whole if nothing sleeping or fixed supports it. The caller makes room for 2 events."""
    fx, fy = -supports.load[i, 0], -supports.load[i, 1]   # what the supports must push with
    force = math.sqrt(fx * fx + fy * fy)
    if force == 0.0:
        return
    left, right = _supports_of(bodies, grid, env, supports, i, fx / force, fy / force)
    if left[1] == NONE and right[1] == NONE:
        return
    supports.load[i, 0] = supports.load[i, 1] = 0.0
    a, b = right, left
    enclosed = a[1] != NONE and b[1] != NONE and b[0] - a[0] < math.pi
    if enclosed and min(-a[0], b[0]) > UPRIGHT:   # N_a a + N_b b = f: Cramer's rule
        determinant = a[2] * b[3] - a[3] * b[2]
        _deliver(log, bodies, env, supports, i, t, a[1], a[2], a[3], (fx * b[3] - fy * b[2]) / determinant)
        _deliver(log, bodies, env, supports, i, t, b[1], b[2], b[3], (a[2] * fy - a[3] * fx) / determinant)
        return
    nearest = a if b[1] == NONE or (a[1] != NONE and -a[0] <= b[0]) else b
    _deliver(log, bodies, env, supports, i, t, nearest[1], nearest[2], nearest[3], fx * nearest[2] + fy * nearest[3])


@njit(cache=True, error_model="numpy")
def note_sleepers(log, bodies, grid, env, supports, particles, count, t):
    """After an event at t involving particles[:count]: those that fell asleep start being
    carried; those woken hand what they owe to their supports, the highest first (wake_up lists
    them upwards), while still where they slept. The caller makes room for 2 count events."""
    for k in range(count - 1, -1, -1):
        i = particles[k]
        if supports.sleeping[i] and not bodies.asleep[i]:
            _owe_weight(bodies, env, supports, i, t)
            pass_on(log, bodies, grid, env, supports, i, t)
            supports.load[i, 0] = supports.load[i, 1] = 0.0
            supports.sleeping[i] = False
    for k in range(count):
        i = particles[k]
        if bodies.asleep[i] and not supports.sleeping[i]:
            _enter(log, bodies, env, supports, i, t)


@njit(cache=True, error_model="numpy")
def carry_sleepers(log, bodies, grid, env, supports, t):
    """At a frame time: every sleeper's weight since last carried joins its load, and the loads
    go down the pile, highest sleeper first. Returns the log (with room made)."""
    count = 0
    for i in range(bodies.radius.shape[0]):
        count += bodies.asleep[i]
    if count == 0:
        return log
    log = with_room(log, 4 * count)
    sleepers, height = np.empty(count, np.int64), np.empty(count)
    count = 0
    for i in range(bodies.radius.shape[0]):
        if bodies.asleep[i]:
            if not supports.sleeping[i]:   # fell asleep at this frame time, or by the budget's fallback
                _enter(log, bodies, env, supports, i, t)
            _owe_weight(bodies, env, supports, i, t)
            sleepers[count] = i
            height[count] = bodies.pos[i, 0] * env.gravity[0] + bodies.pos[i, 1] * env.gravity[1]   # -height
            count += 1
    for k in np.argsort(height, kind="mergesort"):   # highest first
        pass_on(log, bodies, grid, env, supports, sleepers[k], t)
    return log
