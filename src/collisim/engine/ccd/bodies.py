"""Particle state of the event-driven simulation, advanced lazily in closed form.

Between two events a particle moves with constant acceleration, so its state at
any time follows from its state at its own reference time t_ref:

    p(t) = p + v (t - t_ref) + ½ a (t - t_ref)²,    v(t) = v + a (t - t_ref)

Nothing is integrated and no error accumulates between events. Only the
particles taking part in an event are brought up to the event time ("advanced");
the others keep their older reference times (Lubachevsky's lazy update).

Resting. With restitution e < 1 a ball bouncing on a floor makes infinitely many
ever smaller bounces in a finite time (Zeno). Once a rebound would rise less
than REST_HEIGHT × radius, the particle instead *rests* on that support (a box
wall or a segment): its normal velocity is zeroed and the support cancels the
normal part of gravity, so it slides along it with the tangential part of
gravity. Sliding into a second support that it is pressed against (a corner,
the bottom of a V) it is *wedged*: it stays put. A collision with a particle
releases it (then gravity acts again in full, and if it is still pressed into
the support that contact is found at once); so does a collision with an
obstacle that gives it a velocity across its support.
"""
import math
from collections import namedtuple

from ...core.compiling import kernel

Bodies = namedtuple("Bodies", ["pos", "vel", "acc", "t_ref", "radius", "mass", "support", "wedge",
                               "support_normal", "counter", "horizon", "asleep", "last_hit", "slow_since",
                               "last_pair_hit"])
Bodies.__doc__ = """pos, vel, acc (n, 2): state at t_ref (n,); radius, mass (n,).
support (n,) int64: FREE, a wall index, or N_WALLS + segment index for a resting particle;
wedge (n,) int64: its second support when wedged, else FREE; support_normal (n, 2): the
first support's unit normal, pointing at the particle.
counter (n,) int64: events so far, to invalidate older predictions.
horizon (n,) float64: time of the particle's next predicted one-particle event (wall, segment,
cell crossing), after which all its predictions are redone anyway.
asleep (n,) bool: frozen at rest (sleep.py); last_hit (n,): the time of its last collision
(for the TC model, resolve.py); slow_since (n,): the first of the frame times since which it
has been found slow at every frame time (inf: not slow at the last one; sleep.py);
last_pair_hit (n,): the time of its last collision with another particle (TC model)."""

Environment = namedtuple("Environment", ["box", "segments", "gravity", "restitution", "rest_speed", "tc"])
Environment.__doc__ = """box (4,): xmin, ymin, xmax, ymax; segments (m, 4): x0, y0, x1, y1;
gravity (2,); restitution: e in [0, 1]; rest_speed (n,): below it a body held still by its
supports falls asleep (0: never, as with e = 1; sleep.py); tc: Luding and McNamara's TC model's
time (resolve.py; 0: off)."""

FREE = -1
REST_HEIGHT = 1e-9


@kernel
def position_at(bodies, i, t):
    """(x, y) of particle i at time t."""
    dt = t - bodies.t_ref[i]
    return (bodies.pos[i, 0] + (bodies.vel[i, 0] + 0.5 * bodies.acc[i, 0] * dt) * dt,
            bodies.pos[i, 1] + (bodies.vel[i, 1] + 0.5 * bodies.acc[i, 1] * dt) * dt)


@kernel
def velocity_at(bodies, i, t):
    """(vx, vy) of particle i at time t."""
    dt = t - bodies.t_ref[i]
    return bodies.vel[i, 0] + bodies.acc[i, 0] * dt, bodies.vel[i, 1] + bodies.acc[i, 1] * dt


@kernel
def advance(bodies, i, t):
    """Move particle i's reference time to t."""
    bodies.pos[i, 0], bodies.pos[i, 1] = position_at(bodies, i, t)
    bodies.vel[i, 0], bodies.vel[i, 1] = velocity_at(bodies, i, t)
    bodies.t_ref[i] = t


@kernel
def comes_to_rest(env, radius, rebound_speed, nx, ny):
    """Should a particle leaving a support (normal n, pointing at the particle) at
    rebound_speed rest on it instead? Only if gravity presses it into the support
    and the rebound would rise less than REST_HEIGHT × radius."""
    pressing = -(env.gravity[0] * nx + env.gravity[1] * ny)
    return pressing > 0.0 and rebound_speed * rebound_speed <= 2.0 * pressing * REST_HEIGHT * radius


@kernel
def rest_on(bodies, env, i, support, nx, ny):
    """Particle i (current) comes to rest on a support with unit normal n (pointing at
    it): no normal velocity, and the normal part of gravity is cancelled. If it already
    rests on another support and slides into this one, it is wedged: it stops."""
    gx, gy = env.gravity[0], env.gravity[1]
    vx, vy, ax, ay = bodies.vel[i, 0], bodies.vel[i, 1], bodies.acc[i, 0], bodies.acc[i, 1]
    first, wedge = bodies.support[i], bodies.wedge[i]
    first_nx, first_ny = bodies.support_normal[i, 0], bodies.support_normal[i, 1]
    if first != FREE:
        if ax * nx + ay * ny < 0.0:
            wedge = support
            vx = vy = ax = ay = 0.0
    else:
        vn = vx * nx + vy * ny
        gn = gx * nx + gy * ny
        vx -= vn * nx
        vy -= vn * ny
        ax = gx - gn * nx
        ay = gy - gn * ny
        first, first_nx, first_ny = support, nx, ny
    bodies.vel[i, 0], bodies.vel[i, 1], bodies.acc[i, 0], bodies.acc[i, 1] = vx, vy, ax, ay
    bodies.support[i], bodies.wedge[i] = first, wedge
    bodies.support_normal[i, 0], bodies.support_normal[i, 1] = first_nx, first_ny


@kernel
def rests_on(bodies, i, support):
    """Is particle i resting on this support (a wall index or N_WALLS + segment)?"""
    first, second = bodies.support[i], bodies.wedge[i]
    return first == support or second == support


@kernel
def release(bodies, env, i):
    """Particle i (current) no longer rests on anything: full gravity again."""
    bodies.support[i] = bodies.wedge[i] = FREE
    bodies.acc[i, 0], bodies.acc[i, 1] = env.gravity[0], env.gravity[1]


@kernel
def keep_or_release(bodies, env, i):
    """After a collision with an obstacle: particle i keeps resting on its support only
    if its velocity is still along it."""
    if bodies.support[i] == FREE:
        return
    across = bodies.vel[i, 0] * bodies.support_normal[i, 0] + bodies.vel[i, 1] * bodies.support_normal[i, 1]
    if abs(across) > 1e-12 * (abs(bodies.vel[i, 0]) + abs(bodies.vel[i, 1])):
        release(bodies, env, i)


@kernel
def fall_asleep(bodies, i):
    """Particle i (current) is frozen: no velocity, no acceleration, no events of its own."""
    bodies.vel[i, 0] = bodies.vel[i, 1] = bodies.acc[i, 0] = bodies.acc[i, 1] = 0.0
    bodies.asleep[i] = True


@kernel
def wake(bodies, env, i):
    """Particle i (current, asleep) moves again: the acceleration of its resting state."""
    bodies.asleep[i] = False
    bodies.slow_since[i] = math.inf
    bodies.acc[i, 0], bodies.acc[i, 1] = env.gravity[0], env.gravity[1]
    if bodies.wedge[i] != FREE:
        bodies.acc[i, 0] = bodies.acc[i, 1] = 0.0
    elif bodies.support[i] != FREE:
        nx, ny = bodies.support_normal[i, 0], bodies.support_normal[i, 1]
        gn = env.gravity[0] * nx + env.gravity[1] * ny
        bodies.acc[i, 0] -= gn * nx
        bodies.acc[i, 1] -= gn * ny
