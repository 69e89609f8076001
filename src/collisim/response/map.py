"""Bouncing off a collision map: a precomputed signed distance field of the level.

The map answers "how far is the nearest solid, and which way is out?" in O(1) at any point
(statics/collision_map.py: a bilinear sample of a distance grid). A body of radius r touches
the level where that distance is at most r.

Checking only where a step ends would let a fast body jump over a thin wall, so each step's
move is marched from where it began (sphere tracing): at a point whose distance leaves a gap
g = d - r, nothing solid lies within g, so the body may advance that far without touching.
The bilinear field can rise up to sqrt(2) times faster than true distance between samples,
so each advance is g / sqrt(2), and at least a small fraction of a cell so a body gliding
along a wall still makes progress (a wall is at least one cell thick, so that floor cannot
carry the body through it).

At the first point where the gap closes, the normal velocity is reflected with restitution
(v_n -> -e v_n, only when moving into the level), the rest of the move is reflected the same
way and marched again (a few bounces a step at most), and finally the body is pushed out
along the normal to exactly its radius. No speed can carry a body through a wall: a faster
body only takes more march steps, each at least MIN_ADVANCE cells.
"""
import math

from numba import njit

from ..statics.map_field import map_sample

SAFETY = 1.0 / math.sqrt(2.0)   # the bilinear field's slope is at most sqrt(2) times the distance's
MIN_ADVANCE = 0.125             # cells: the smallest march step
BOUNCES_PER_STEP = 4            # reflections of one step's move before the body stops at the contact
PUSH_OUT_ROUNDS = 4             # the normal of a bilinear field is not exact: push out a few times


@njit(cache=True, error_model="numpy")
def march(field, x, y, dx, dy, radius):
    """How far along the move (x, y) -> (x + dx, y + dy) a body of `radius` goes before it
    touches the map while heading into it: the fraction f in [0, 1] of the move at contact,
    or 2.0 if it never does. A body touching the map but moving away is not stopped."""
    length = math.hypot(dx, dy)
    if length == 0.0:
        return 2.0
    floor = MIN_ADVANCE * field.cell
    travelled = 0.0
    while True:
        f = travelled / length
        d, nx, ny = map_sample(field, x + f * dx, y + f * dy)
        gap = d - radius
        if gap <= 0.0 and dx * nx + dy * ny < 0.0:
            return f
        if travelled >= length:
            return 2.0
        travelled = min(length, travelled + max(gap * SAFETY, floor))


@njit(cache=True, error_model="numpy")
def _outward(field, x, y, dx, dy):
    """The map's unit normal at (x, y), or straight back along the move where the field has
    none (deep inside solid, or on a ridge)."""
    _, nx, ny = map_sample(field, x, y)
    if nx != 0.0 or ny != 0.0:
        return nx, ny
    length = math.hypot(dx, dy)
    return (-dx / length, -dy / length) if length > 0.0 else (0.0, 1.0)


@njit(cache=True, error_model="numpy")
def push_out(field, positions, radius, i):
    """Move body i along the map's normal until it is its radius from the solid."""
    for _ in range(PUSH_OUT_ROUNDS):
        d, nx, ny = map_sample(field, positions[i, 0], positions[i, 1])
        if d >= radius or (nx == 0.0 and ny == 0.0):
            return
        positions[i, 0] += (radius - d) * nx
        positions[i, 1] += (radius - d) * ny


@njit(cache=True, error_model="numpy")
def bounce_off_map(field, start, positions, velocities, accelerations, radii, masses, restitution, dt, i):
    """Body i moved from start[i] to positions[i] this step (under its constant acceleration,
    for dt): march that move against the map and bounce at each contact, in place. Returns
    (impulse of the first bounce or 0, its contact point x, y, bounces)."""
    x, y = start[i, 0], start[i, 1]
    dx, dy = positions[i, 0] - x, positions[i, 1] - y
    ax, ay = accelerations[i, 0], accelerations[i, 1]
    # energy per unit mass at the start of the step, ½|v|² - a·p (constant in free flight)
    vx0, vy0 = velocities[i, 0] - ax * dt, velocities[i, 1] - ay * dt
    energy = 0.5 * (vx0 * vx0 + vy0 * vy0) - (ax * x + ay * y)
    first_impulse, cx, cy, bounces = 0.0, x, y, 0
    for _ in range(BOUNCES_PER_STEP):
        f = march(field, x, y, dx, dy, radii[i])
        if f > 1.0:
            x, y, dx, dy = x + dx, y + dy, 0.0, 0.0
            break
        x, y = x + f * dx, y + f * dy
        dx, dy = (1.0 - f) * dx, (1.0 - f) * dy     # the rest of the move, reflected below
        nx, ny = _outward(field, x, y, dx, dy)
        into = dx * nx + dy * ny
        dx -= (1.0 + restitution) * min(into, 0.0) * nx
        dy -= (1.0 + restitution) * min(into, 0.0) * ny
        approach = velocities[i, 0] * nx + velocities[i, 1] * ny
        if approach < 0.0:
            energy -= 0.5 * (1.0 - restitution * restitution) * approach * approach   # what e < 1 takes
            velocities[i, 0] -= (1.0 + restitution) * approach * nx
            velocities[i, 1] -= (1.0 + restitution) * approach * ny
            if bounces == 0:
                first_impulse = -(1.0 + restitution) * approach * masses[i]
                cx, cy = x - radii[i] * nx, y - radii[i] * ny
            bounces += 1
    # after BOUNCES_PER_STEP contacts in one step the body stays at the last one
    positions[i, 0], positions[i, 1] = x, y
    push_out(field, positions, radii[i], i)
    if bounces > 0:
        _keep_energy(velocities, i, energy + ax * positions[i, 0] + ay * positions[i, 1])
    return first_impulse, cx, cy, bounces


@njit(cache=True, error_model="numpy")
def _keep_energy(velocities, i, kinetic):
    """Scale body i's speed so its kinetic energy per unit mass is `kinetic` (0 if negative).

    The bounce reflects velocity at the contact but the move as a straight chord, and under an
    acceleration the two disagree by about a·dt per bounce; left alone, that gains or loses
    energy at every bounce, as the walls would without their own correction
    (response/statics.py). Matching the speed to the energy the body had, minus what the
    restitution took, keeps an elastic bounce elastic."""
    speed = math.hypot(velocities[i, 0], velocities[i, 1])
    if speed == 0.0:
        return
    scale = math.sqrt(max(2.0 * kinetic, 0.0)) / speed
    velocities[i, 0] *= scale
    velocities[i, 1] *= scale
