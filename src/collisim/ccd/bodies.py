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
gravity. Any later collision releases it (then gravity acts again in full, and
if it is still pressed into the support that contact is found at once).
"""
from collections import namedtuple

from numba import njit

Bodies = namedtuple("Bodies", ["pos", "vel", "acc", "t_ref", "radius", "mass", "support", "counter", "horizon"])
Bodies.__doc__ = """pos, vel, acc (n, 2): state at t_ref (n,); radius, mass (n,).
support (n,) int64: FREE, a wall index, or N_WALLS + segment index for a resting particle.
counter (n,) int64: events so far, to invalidate older predictions.
horizon (n,) float64: time of the particle's next predicted one-particle event (wall, segment,
cell crossing), after which all its predictions are redone anyway."""

Scene = namedtuple("Scene", ["box", "segments", "gravity", "restitution"])
Scene.__doc__ = """box (4,): xmin, ymin, xmax, ymax; segments (m, 4): x0, y0, x1, y1;
gravity (2,); restitution: e in [0, 1]."""

FREE = -1
N_WALLS = 4  # 0 left, 1 right, 2 bottom, 3 top
REST_HEIGHT = 1e-9


@njit(cache=True)
def position_at(bodies, i, t):
    """(x, y) of particle i at time t."""
    dt = t - bodies.t_ref[i]
    return (bodies.pos[i, 0] + (bodies.vel[i, 0] + 0.5 * bodies.acc[i, 0] * dt) * dt,
            bodies.pos[i, 1] + (bodies.vel[i, 1] + 0.5 * bodies.acc[i, 1] * dt) * dt)


@njit(cache=True)
def velocity_at(bodies, i, t):
    """(vx, vy) of particle i at time t."""
    dt = t - bodies.t_ref[i]
    return bodies.vel[i, 0] + bodies.acc[i, 0] * dt, bodies.vel[i, 1] + bodies.acc[i, 1] * dt


@njit(cache=True)
def advance(bodies, i, t):
    """Move particle i's reference time to t."""
    bodies.pos[i, 0], bodies.pos[i, 1] = position_at(bodies, i, t)
    bodies.vel[i, 0], bodies.vel[i, 1] = velocity_at(bodies, i, t)
    bodies.t_ref[i] = t


@njit(cache=True)
def wall_geometry(box, wall, radius):
    """(axis, bound, inward) of a wall: the coordinate axis it stops, the value of
    that coordinate for a centre touching it, and the sign of its inward normal."""
    axis = wall // 2
    if wall % 2 == 0:
        return axis, box[axis] + radius, 1.0
    return axis, box[2 + axis] - radius, -1.0


@njit(cache=True)
def comes_to_rest(scene, radius, rebound_speed, nx, ny):
    """Should a particle leaving a support (normal n, pointing at the particle) at
    rebound_speed rest on it instead? Only if gravity presses it into the support
    and the rebound would rise less than REST_HEIGHT × radius."""
    pressing = -(scene.gravity[0] * nx + scene.gravity[1] * ny)
    return pressing > 0.0 and rebound_speed * rebound_speed <= 2.0 * pressing * REST_HEIGHT * radius


@njit(cache=True)
def rest_on(bodies, scene, i, support, nx, ny):
    """Particle i (current) rests on a support with unit normal n: no normal
    velocity, and the normal part of gravity is cancelled."""
    vn = bodies.vel[i, 0] * nx + bodies.vel[i, 1] * ny
    gn = scene.gravity[0] * nx + scene.gravity[1] * ny
    bodies.vel[i, 0] -= vn * nx
    bodies.vel[i, 1] -= vn * ny
    bodies.acc[i, 0] = scene.gravity[0] - gn * nx
    bodies.acc[i, 1] = scene.gravity[1] - gn * ny
    bodies.support[i] = support


@njit(cache=True)
def release(bodies, scene, i):
    """Particle i (current) no longer rests on anything: full gravity again."""
    bodies.support[i] = FREE
    bodies.acc[i, 0], bodies.acc[i, 1] = scene.gravity[0], scene.gravity[1]
