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

The box's walls are met inside the same march: where the move reaches a wall before the map,
the rest of it is reflected there and marched on. (Reflected afterwards by the walls' own
bounce, the rest of a step that went past the wall came back without looking at the map: a
ball between a painted wall and the box wall crossed the painted wall at 3.3 units a frame.)

A body meeting the map no faster than the rest speed (statics' rest_speed: twice what the
acceleration adds in a step) is resting or sliding on it, not hitting it: its velocity loses
the part into the map and nothing more, the rest of its move goes on along the surface, and no
collision is counted. Contacts along that same surface (normals within SLIDE_COS of it) do not
stop the march again in the step; the push-out at the end puts the body back on it.
"""
import math

from ..core.compiling import kernel

from ..core.geometry.box import centre_range
from .impulse import newton_impulse
from ..statics.map_field import DEPTH_SLACK, map_contact, map_sample

SAFETY = 1.0 / math.sqrt(2.0)   # the bilinear field's slope is at most sqrt(2) times the distance's
MIN_ADVANCE = 0.125             # cells: the smallest march step
BOUNCES_PER_STEP = 4            # reflections of one step's move before the body stops at the contact
PUSH_OUT_ROUNDS = 4             # the normal of a bilinear field is not exact: push out a few times
SLIDE_COS = math.cos(math.radians(30.0))   # contacts this close in direction are the surface slid on
# A field normal this close to the surface slid on is that surface, read across the body or not
# (a staircase's field normals stray up to 18 degrees from the across-body one): the march need
# not read the contact across the body there, the costly part of its sampling.
ALONG_COS = math.cos(math.radians(12.0))


@kernel
def march(field, x, y, dx, dy, radius, sx, sy):
    """How far along the move (x, y) -> (x + dx, y + dy) a body of `radius` goes before it
    touches the map while heading into it: the fraction f in [0, 1] of the move at contact,
    or 2.0 if it never does. A body touching the map but moving away is not stopped, nor one
    touching it where its normal lies within SLIDE_COS of (sx, sy), the surface it slides on
    ((0, 0): none)."""
    length = math.hypot(dx, dy)
    if length == 0.0:
        return 2.0
    floor = MIN_ADVANCE * field.cell
    slack = DEPTH_SLACK * field.cell   # the contact's depth is within this of the field's (map_contact)
    travelled = 0.0
    while True:
        f = travelled / length
        d, ex, ey = map_sample(field, x + f * dx, y + f * dy)
        gap = d - radius
        if gap <= slack and ex * sx + ey * sy <= ALONG_COS:
            depth, nx, ny = map_contact(field, x + f * dx, y + f * dy, radius)
            if depth <= radius and dx * nx + dy * ny < 0.0 and nx * sx + ny * sy <= SLIDE_COS:
                return f
        if travelled >= length:
            return 2.0
        travelled = min(length, travelled + max((gap - slack) * SAFETY, floor))


@kernel
def _outward(field, x, y, dx, dy, radius):
    """The map's unit normal for a body of radius at (x, y) (map_contact), or straight back along
    the move where the field has none (deep inside solid, or on a ridge)."""
    _, nx, ny = map_contact(field, x, y, radius)
    if nx != 0.0 or ny != 0.0:
        return nx, ny
    length = math.hypot(dx, dy)
    return (-dx / length, -dy / length) if length > 0.0 else (0.0, 1.0)


@kernel
def _contact_point(field, x, y, radius, nx, ny):
    """Where a body of radius centred at (x, y) touches the map: a radius along the field's own
    normal at the centre, which points at the nearest solid (the contact normal, taken across
    the body, can miss a sharp corner by a fraction of the radius); along (nx, ny) where the field
    has none."""
    _, fx, fy = map_sample(field, x, y)
    if fx == 0.0 and fy == 0.0:
        fx, fy = nx, ny
    return x - radius * fx, y - radius * fy


@kernel
def push_out(field, positions, radius, i):
    """Move body i along the map's normal until it is its radius from the solid."""
    if map_sample(field, positions[i, 0], positions[i, 1])[0] >= radius + DEPTH_SLACK * field.cell:
        return   # clear of the map whichever way it is read (map_contact's depth is within the slack)
    for _ in range(PUSH_OUT_ROUNDS):
        d, nx, ny = map_contact(field, positions[i, 0], positions[i, 1], radius)
        if d >= radius or (nx == 0.0 and ny == 0.0):
            return
        positions[i, 0] += (radius - d) * nx
        positions[i, 1] += (radius - d) * ny


@kernel
def _box_fraction(box, held, i, x, y, dx, dy, radius):
    """(f, side): the fraction of the move at which body i first reaches a box wall while moving
    out through it (0 if already past it), and the wall's side (2 axis + high); (2.0, -1) if it
    does not. Axes on which the contact solver held the body (held[i, axis]) are left to it."""
    first, side = 2.0, -1
    for axis in range(2):
        if held[i, axis]:
            continue
        low, high = centre_range(box, axis, radius)
        p, d = (x, dx) if axis == 0 else (y, dy)
        if d > 0.0 and p + d > high:
            f, wall = max((high - p) / d, 0.0), 2 * axis + 1
        elif d < 0.0 and p + d < low:
            f, wall = max((low - p) / d, 0.0), 2 * axis
        else:
            continue
        if f < first:
            first, side = f, wall
    return first, side


@kernel
def _off_wall(velocities, masses, restitution, i, side):
    """Reflect body i's velocity off box wall `side` if it moves out through it: (the impulse,
    the kinetic energy per unit mass the restitution took); (0, 0) if it does not."""
    axis = side // 2
    v = velocities[i, axis]
    if (v <= 0.0) if side % 2 == 1 else (v >= 0.0):
        return 0.0, 0.0
    velocities[i, axis] = -restitution * v
    return newton_impulse(-abs(v), restitution, masses[i]), 0.5 * (1.0 - restitution * restitution) * v * v


@kernel
def bounce_off_map(field, box, held, start, positions, velocities, accelerations, radii, masses, restitution,
                   rest_speed, dt, i, wall_impulses):
    """Body i moved from start[i] to positions[i] this step (under its constant acceleration,
    for dt): march that move against the map and the box walls and bounce at each contact, in
    place (the module). held (n, >= 2) bool: the axes on which the solver held body i against a
    wall. wall_impulses (4,) receives the first impulse off each wall side (0: none). Returns
    (impulse of the first bounce off the map or 0, its contact point x, y, bounces off the map,
    bounces off the walls)."""
    x, y = start[i, 0], start[i, 1]
    dx, dy = positions[i, 0] - x, positions[i, 1] - y
    ax, ay = accelerations[i, 0], accelerations[i, 1]
    # energy per unit mass at the start of the step, ½|v|² - a·p (constant in free flight)
    vx0, vy0 = velocities[i, 0] - ax * dt, velocities[i, 1] - ay * dt
    energy = 0.5 * (vx0 * vx0 + vy0 * vy0) - (ax * x + ay * y)
    first_impulse, cx, cy, bounces, wall_bounces = 0.0, x, y, 0, 0
    sx, sy = 0.0, 0.0   # the surface the body slides on, once it meets one slowly
    for _ in range(BOUNCES_PER_STEP):
        f = march(field, x, y, dx, dy, radii[i], sx, sy)
        fb, side = _box_fraction(box, held, i, x, y, dx, dy, radii[i])
        if f > 1.0 and fb > 1.0:
            x, y, dx, dy = x + dx, y + dy, 0.0, 0.0
            break
        if fb <= f:   # a box wall first: the rest of the move is reflected there
            x, y, dx, dy = x + fb * dx, y + fb * dy, (1.0 - fb) * dx, (1.0 - fb) * dy
            if side // 2 == 0:
                dx = -restitution * dx
            else:
                dy = -restitution * dy
            impulse, lost = _off_wall(velocities, masses, restitution, i, side)
            if impulse > 0.0:
                energy -= lost
                wall_impulses[side] = impulse if wall_impulses[side] == 0.0 else wall_impulses[side]
                wall_bounces += 1
            continue
        x, y = x + f * dx, y + f * dy
        dx, dy = (1.0 - f) * dx, (1.0 - f) * dy     # the rest of the move, reflected below
        nx, ny = _outward(field, x, y, dx, dy, radii[i])
        into = dx * nx + dy * ny
        approach = velocities[i, 0] * nx + velocities[i, 1] * ny
        if -approach <= rest_speed:   # resting or sliding on the map: no bounce (the module)
            dx, dy = dx - min(into, 0.0) * nx, dy - min(into, 0.0) * ny
            if approach < 0.0:
                energy -= 0.5 * approach * approach
                velocities[i, 0] -= approach * nx
                velocities[i, 1] -= approach * ny
            sx, sy = nx, ny
            continue
        dx -= (1.0 + restitution) * min(into, 0.0) * nx
        dy -= (1.0 + restitution) * min(into, 0.0) * ny
        energy -= 0.5 * (1.0 - restitution * restitution) * approach * approach   # what e < 1 takes
        velocities[i, 0] -= (1.0 + restitution) * approach * nx
        velocities[i, 1] -= (1.0 + restitution) * approach * ny
        if bounces == 0:
            first_impulse = newton_impulse(approach, restitution, masses[i])
            cx, cy = _contact_point(field, x, y, radii[i], nx, ny)
        bounces += 1
    # after BOUNCES_PER_STEP contacts in one step the body stays at the last one
    positions[i, 0], positions[i, 1] = x, y
    push_out(field, positions, radii[i], i)
    if bounces + wall_bounces > 0:
        _keep_energy(velocities, i, energy + ax * positions[i, 0] + ay * positions[i, 1])
    return first_impulse, cx, cy, bounces, wall_bounces


@kernel
def glide_past_map(field, box, held, start, positions, velocities, accelerations, radii, masses, restitution,
                   rest_speed, dt, i, wall_impulses):
    """Body i, held against the map by the contact solver this step, moved from start[i] to
    positions[i]: march that move as bounce_off_map does, sliding on the surface that holds it
    (contacts along the map's normal at the start do not stop it), so a step never carries it
    through another painted wall or past the box. Returns bounce_off_map's answer."""
    _, nx, ny = map_contact(field, start[i, 0], start[i, 1], radii[i])
    x, y = start[i, 0], start[i, 1]
    dx, dy = positions[i, 0] - x, positions[i, 1] - y
    f = march(field, x, y, dx, dy, radii[i], nx, ny)
    fb, _ = _box_fraction(box, held, i, x, y, dx, dy, radii[i])
    if f > 1.0 and fb > 1.0:   # nothing else met: as the solver left it, back on the surface
        push_out(field, positions, radii[i], i)
        return 0.0, x, y, 0, 0
    return bounce_off_map(field, box, held, start, positions, velocities, accelerations, radii, masses, restitution,
                          rest_speed, dt, i, wall_impulses)


@kernel
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
