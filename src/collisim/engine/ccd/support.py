"""The impulse that supports give the bodies resting on them, logged for the wall pressure.

A body resting on a wall or a segment (bodies.py) is pushed by it with a constant normal
force for as long as it rests: N = m (-g·n) on one support of unit normal n, or, wedged
between two supports, the two forces N1 n1 + N2 n2 = -m g that hold it still. No collision
happens, so without this the log (and the pressure measured from it, analysis/metrics.py)
would miss the weight of everything at rest.

What the supports of each body push with is recorded whenever its resting changes (after
each event it took part in): its supports and their forces, and since when. The impulse
N · (t - since) of each support is logged as a kinds.SUPPORT event of that wall or segment at
the moment the resting changes, and at every frame time for the bodies still resting, so a
body at rest on the floor gives the floor m·g·dt per frame. These events are not impacts:
they are not counted in the per-frame collision counts, and the player does not flash them.
"""
from collections import namedtuple

import numpy as np

from ...core.compiling import compiled, kernel
from ...core.geometry.box import wall_geometry
from ...core.geometry.segment import segment_contact
from ...core.kinds import N_WALLS, SUPPORT
from ..eventlog import append, with_room
from .bodies import FREE, position_at

Supports = namedtuple("Supports", ["support", "force", "since", "sleeping", "load", "order", "plan", "normal",
                                   "state"])
Supports.__doc__ = """What the supports of each body push with, as last recorded: support (n, 2)
int64 the supports (as Bodies.support and wedge, FREE for none); force (n, 2) their normal
forces; since (n,) the time from which their impulse (or, asleep, its weight) is not logged
yet. sleeping (n,) bool: asleep as far as the log knows, its weight carried down the pile
instead (carried.py); load (n, 2): the impulse a sleeper has yet to pass on to its supports;
order (n,) int64: the sleepers, highest first; plan (n, 2) int64 and normal (n, 4): the two
supports that carry each one and their normals; state (3,) int64: the number of sleepers in
order, whether anything changed since the last frame time, whether the plan may be reused."""


def new_supports(n):
    """No body resting, at t = 0."""
    return Supports(np.full((n, 2), FREE, np.int64), np.zeros((n, 2)), np.zeros(n), np.zeros(n, np.bool_),
                    np.zeros((n, 2)), np.zeros(n, np.int64), np.zeros((n, 2), np.int64), np.zeros((n, 4)),
                    np.zeros(3, np.int64))


@kernel
def support_normal(bodies, env, i, support):
    """Unit normal (pointing at particle i, current) of a wall index or N_WALLS + segment."""
    if support < N_WALLS:
        axis, _, inward = wall_geometry(env.box, support, bodies.radius[i])
        return (inward, 0.0) if axis == 0 else (0.0, inward)
    nx, ny = segment_contact(bodies.pos[i, 0], bodies.pos[i, 1], env.segments[support - N_WALLS])[:2]
    return nx, ny


@kernel
def support_forces(bodies, env, i):
    """The normal forces (N1, N2) of particle i's support and wedge (0 where none)."""
    first, second = bodies.support[i], bodies.wedge[i]
    if first == FREE:
        return 0.0, 0.0
    m, gx, gy = bodies.mass[i], env.gravity[0], env.gravity[1]
    ax, ay = support_normal(bodies, env, i, first)
    if second == FREE:
        return m * max(-(gx * ax + gy * ay), 0.0), 0.0
    bx, by = support_normal(bodies, env, i, second)
    # N1 a + N2 b = -m g: Cramer's rule
    determinant = ax * by - ay * bx
    if determinant == 0.0:
        return m * max(-(gx * ax + gy * ay), 0.0), 0.0
    return (m * max((-gx * by + gy * bx) / determinant, 0.0),
            m * max((-ax * gy + ay * gx) / determinant, 0.0))


@kernel
def log_impulses(log, bodies, env, supports, i, t):
    """Log the impulse particle i's recorded supports gave it since `since`, up to t."""
    duration = t - supports.since[i]
    for k in range(2):
        s = supports.support[i, k]
        if s == FREE or not supports.force[i, k] * duration > 0.0:
            continue
        x, y = position_at(bodies, i, t)
        nx, ny = support_normal(bodies, env, i, s)
        r = bodies.radius[i]
        append(log, t, SUPPORT, i, s, supports.force[i, k] * duration, x - r * nx, y - r * ny)
    supports.since[i] = t


@kernel
def note_supports(log, bodies, env, supports, particles, count, t):
    """After an event at time t involving particles[:count] (current): log what their supports
    gave them up to t where their resting changed, and record the new supports. The caller makes
    room for 2 count events in the log (with_room): run at every event, it allocates nothing."""
    for k in range(count):
        i = particles[k]
        if supports.sleeping[i] or (bodies.support[i] == supports.support[i, 0]
                                    and bodies.wedge[i] == supports.support[i, 1]):
            continue   # unchanged, or asleep: its weight is carried (carried.py)
        log_impulses(log, bodies, env, supports, i, t)
        supports.support[i, 0], supports.support[i, 1] = bodies.support[i], bodies.wedge[i]
        supports.force[i, 0], supports.force[i, 1] = support_forces(bodies, env, i)


@compiled(error_model="numpy")
def log_frame_supports(log, bodies, env, supports, t):
    """At a frame time: log what every resting particle's supports gave it since last logged
    (not the sleepers': their weight is carried, carried.py)."""
    n = bodies.radius.shape[0]
    resting = 0
    for i in range(n):
        resting += supports.support[i, 0] != FREE and not supports.sleeping[i]
    log = with_room(log, 2 * resting)
    for i in range(n):
        if supports.support[i, 0] != FREE and not supports.sleeping[i]:
            log_impulses(log, bodies, env, supports, i, t)
    return log
