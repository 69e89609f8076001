"""Sleeping: bodies at rest on other bodies cost nothing until something hits them.

Resting on a wall or a segment is exact (bodies.py): the support cancels the normal part of
gravity. Resting on other *particles* is not: a ball in the cradle of two balls would bounce
on them for ever (Zeno), and a pile keeps every ball bouncing (inelastic collapse). So, as
event-driven granular codes do, a body that is held still is frozen ("asleep"):

* A body *falls asleep* when it moves slower than the rest speed (Environment.rest_speed,
  settable; by default the speed of a bounce SLEEP_HEIGHT × its radius high) while it is
  *cradled*: gravity is balanced by non-negative pushes from what it touches — the walls and
  segments it rests on (bodies.py), those it touches that gravity does not press it into (a
  ball pressed into a side wall by the ball under it is held), and the bodies already asleep,
  all within SLEEP_GAP × its radius. A floor or a slope counts only once the body rests on it,
  or at the instant it hits it: a ball still bouncing on the floor would otherwise freeze up
  to SLEEP_GAP × r in the air, and its weight would never reach the floor (support.py). One
  that falls asleep as it hits a floor or a slope rests on it, exactly on it (a ball squeezed
  between the floor and a sleeper above would otherwise rattle between the two, thousands of
  times a frame, until the event budget ran out). For frictionless disks that
  means -g lies in the cone of those contact normals: one support straight under it, or two
  on either side of the vertical. This is tested right after each collision of a slow body and,
  for every body, at each frame time; a pile thus falls asleep from the floor up.
  Bodies that lean on each other (an arch, a row pressed together) would wait for one
  another's sleep for ever, so at frame times a body that touches another one lower than
  itself and has been slow at every frame time for SLOW_SPEEDS × rest speed / |g| falls
  asleep too: unsupported, gravity would have changed its speed by more than that meanwhile.
  A cradled body hit twice at the same instant is jammed (wedged into a narrow cradle it
  cannot get out of) and falls asleep whatever its speed. Only when e < 1: an elastic system
  has no rest to come to.
* A contact that *gives way* delays sleep (leaning.yields): frictionless, a floor holds a body up but
  not in place, so a body that an awake one leans on from above, off the vertical, is pushed
  aside if nothing beside it holds it, and the leaning one comes down. Neither sleeps while
  that lasts (the bottom balls of a pyramid slide apart under the top one, which ends on the
  floor, as without sleeping), unless it has been slow for SLOW_SPEEDS_GIVING_WAY rest speeds'
  worth of gravity: a jam that only rattles in place must still come to rest.
* A sleeping body has no velocity, no acceleration and no events of its own; another body
  collides with it as with a fixed obstacle (resolve.py), so a settled pile costs nothing.
* A body that hits a sleeping one faster than the sleeper's rest speed *wakes* it (the
  collision is then an ordinary one, between two free bodies), and with it every sleeping
  body resting on it, and on those, upwards: nothing is left hanging in the air. A sleeper
  left with nothing under it (what held it up has moved away) wakes at the next frame time
  and falls (carried.py).

Falling asleep removes at most ½ m v_rest² of kinetic energy per body: with the suggested
rest speed, a bounce of a thousandth of a radius.

Status: ON BY DEFAULT under gravity when e < 1 (default_rest_speed); rest_speed 0 turns it
off; without gravity or with e = 1 the default is 0, so gases run byte for byte as before.
Measured (benchmarks/ccd_settling.py): the settling particles_250 gas (e = 0.8, default rest
speed, 60 s) has no frame over the budget, memory flat, overlaps ~1e-14 r, and costs 3.0-3.1x
the discrete method at one substep never asleep per simulated second (about 14x the discrete
method with its own sleeping, engine/islands.py). A sleeper's weight goes on to the
walls through the pile under it (carried.py), so a sleeping pile presses the floor with all
its weight. Known limits: piles freeze looser than hexagonal close packing, as random drops do in
every engine. 200 balls dropped at random (seeds 1 to 4), 10 s, with the default TC model
(resolve.py): mean heights +8.8 % (e = 0), +8.9 % (e = 0.5), +5.1 % (e = 0.9) above close
packing, against +7.4, +6.2 and +6.4 % for the pymunk comparison mirror's piles from the same
drops (10 substeps) and +9.4, +9.2 and +6.2 % for the discrete method's. A ball in a row on the
floor, woken by a hard hit from the bodies still bouncing above it, can rattle with its
neighbours in zero gaps until the event budget runs out; the budget's fallback then freezes the
storm and lets the rest of the frame go on (fallback.py), so that those above settle.
"""
import math

from ...core.compiling import kernel
from ...core.geometry.box import wall_geometry
from ...core.geometry.segment import segment_contact
from ...core.kinds import N_WALLS, PAIR, WALL
from ...broadphase.cells import reach_block, segment_range
from .bodies import REST_HEIGHT, advance, fall_asleep, position_at, rest_on, rests_on, velocity_at, wake
from .leaning import SLEEP_GAP, UPRIGHT, leans_on_a_body, yields

# A body slow at every frame time for as long as gravity takes to change a speed by this many
# rest speeds is carried by what it touches, whether or not those sleep yet.
SLOW_SPEEDS = 4.0
# As long for a body in a contact that gives way (leaning.yields): what makes it slide starts
# slowly (a pyramid's top ball comes down at about a seventh of g at first), but a jam that only
# rattles in place must still come to rest.
SLOW_SPEEDS_GIVING_WAY = 40.0


@kernel
def _widen(ux, uy, nx, ny, right, left):
    """Fold a support normal n into the two normals nearest the up direction u on each side:
    right (angle <= 0 from u, the largest) and left (angle >= 0, the smallest)."""
    angle = math.atan2(ux * ny - uy * nx, ux * nx + uy * ny)
    if angle <= 0.0:
        right = max(right, angle)
    if angle >= 0.0:
        left = min(left, angle)
    return right, left


@kernel
def cradled(bodies, grid, env, i, t, hitting):
    """Is particle i at time t held against gravity by the walls, segments and sleeping bodies
    it touches (to within SLEEP_GAP of its radius)? See the module docstring. hitting: i has
    just collided, so a wall or segment it is on (to within REST_HEIGHT of its radius: the one
    it hit) counts whether or not it rests there."""
    gravity = math.hypot(env.gravity[0], env.gravity[1])
    if gravity == 0.0:
        return False
    ux, uy = -env.gravity[0] / gravity, -env.gravity[1] / gravity
    x, y = position_at(bodies, i, t)
    r = bodies.radius[i]
    right, left = -10.0, 10.0   # no support on either side yet
    gap = SLEEP_GAP * r
    for wall in range(N_WALLS):   # a wall it touches pushes it along the wall's normal
        axis, bound, inward = wall_geometry(env.box, wall, r)
        nx, ny = (inward, 0.0) if axis == 0 else (0.0, inward)
        off = abs((x, y)[axis] - bound)
        if rests_on(bodies, i, wall) or (hitting and off <= REST_HEIGHT * r) or \
                (off <= gap and nx * ux + ny * uy <= 0.0):
            right, left = _widen(ux, uy, nx, ny, right, left)
    first, last, every = segment_range(grid, i, env.segments.shape[0])
    for k in range(first, last):
        segment = k if every else grid.segment_index[k]
        nx, ny, distance = segment_contact(x, y, env.segments[segment])[:3]
        if rests_on(bodies, i, N_WALLS + segment) or (hitting and distance - r <= REST_HEIGHT * r) or \
                (distance - r <= gap and nx * ux + ny * uy <= 0.0):
            right, left = _widen(ux, uy, nx, ny, right, left)
    cx_lo, cx_hi, cy_lo, cy_hi = reach_block(grid, grid.cell[i], grid.reach[i])
    for cy in range(cy_lo, cy_hi):
        for cx in range(cx_lo, cx_hi):
            j = grid.head[cy * grid.nx + cx]
            while j >= 0:
                if j != i and bodies.asleep[j]:
                    right, left = _support_of(bodies, i, j, x, y, ux, uy, right, left)
                j = grid.next[j]
    for k in range(grid.apart.shape[0]):
        j = grid.apart[k]
        if j != i and bodies.asleep[j]:
            right, left = _support_of(bodies, i, j, x, y, ux, uy, right, left)
    return right >= -UPRIGHT or left <= UPRIGHT or left - right < math.pi


@kernel
def _sleep_on_what_it_hits(bodies, env, contacts, i):
    """Particle i (current, just collided) falls asleep. On each wall or segment it has just hit
    that gravity presses it into, it rests too: the support then carries its weight (support.py)
    and it wakes resting there (bodies.wake). The rebound it is not given comes off that
    contact's impulse, as when a bounce too small to matter ends in resting (resolve.py)."""
    gx, gy = env.gravity[0], env.gravity[1]
    for k in range(contacts.count[0]):
        if contacts.i[k] != i or contacts.kind[k] == PAIR:
            continue
        nx, ny = -contacts.nx[k], -contacts.ny[k]   # from the obstacle towards the particle
        if gx * nx + gy * ny < 0.0:
            rebound = bodies.vel[i, 0] * nx + bodies.vel[i, 1] * ny
            contacts.impulse[k] -= bodies.mass[i] * max(rebound, 0.0)
            support = contacts.other[k] if contacts.kind[k] == WALL else N_WALLS + contacts.other[k]
            rest_on(bodies, env, i, support, nx, ny)
    fall_asleep(bodies, i)


@kernel
def _support_of(bodies, i, j, x, y, ux, uy, right, left):
    """Fold sleeping body j into i's supports if it touches i (at x, y)."""
    dx, dy = x - bodies.pos[j, 0], y - bodies.pos[j, 1]
    distance = math.sqrt(dx * dx + dy * dy)
    if distance - bodies.radius[i] - bodies.radius[j] <= SLEEP_GAP * min(bodies.radius[i], bodies.radius[j]):
        return _widen(ux, uy, dx / distance, dy / distance, right, left)
    return right, left


@kernel
def slow(bodies, env, i, t):
    """Is particle i (awake) moving slower than its rest speed at time t?"""
    vx, vy = velocity_at(bodies, i, t)
    return vx * vx + vy * vy < env.rest_speed[i] * env.rest_speed[i]


@kernel
def doze(bodies, grid, env, contacts, particles, count, t):
    """Put to sleep those of particles[:count] (current at t, just collided) that are cradled
    and slow, or jammed: hit again at the same instant (last_hit == t, before this collision
    is marked), as a body wedged between two supports into which it keeps falling."""
    for k in range(count):
        i = particles[k]
        if not bodies.asleep[i] and env.rest_speed[i] > 0.0 and (bodies.last_hit[i] == t or slow(bodies, env, i, t)) \
                and cradled(bodies, grid, env, i, t, True) and not yields(bodies, grid, env, i, t):
            _sleep_on_what_it_hits(bodies, env, contacts, i)


@kernel
def doze_all(bodies, grid, env, t, fell):
    """At a frame time: put to sleep every slow body that is cradled, or that touches another
    body and has been slow at every frame time for SLOW_SPEEDS rest speeds' worth of gravity
    (module docstring). Bodies are brought to time t. Fills fell with them and returns their
    number."""
    count = 0
    gravity = math.hypot(env.gravity[0], env.gravity[1])
    for i in range(bodies.radius.shape[0]):
        if bodies.asleep[i] or env.rest_speed[i] == 0.0:
            continue
        if not slow(bodies, env, i, t):
            bodies.slow_since[i] = math.inf
            continue
        bodies.slow_since[i] = min(bodies.slow_since[i], t)
        slow_for = (t - bodies.slow_since[i]) * gravity / env.rest_speed[i]   # in rest speeds' worth of gravity
        carried = slow_for >= SLOW_SPEEDS and leans_on_a_body(bodies, grid, env, i, t)
        if (carried or cradled(bodies, grid, env, i, t, False)) and \
                (slow_for >= SLOW_SPEEDS_GIVING_WAY or not yields(bodies, grid, env, i, t)):
            advance(bodies, i, t)
            fall_asleep(bodies, i)
            fell[count] = i
            count += 1
    return count


@kernel
def wake_up(bodies, grid, env, k, t, involved, count, listed):
    """Wake sleeping body k (involved already) and every sleeping body resting on it, and on
    those, upwards (and on the bodies involved after k: they move too); each is added to
    involved (listed marks who is in it). Returns the count."""
    wake(bodies, env, k)
    gravity = math.hypot(env.gravity[0], env.gravity[1])
    ux, uy = -env.gravity[0] / gravity, -env.gravity[1] / gravity
    queue = 0
    while involved[queue] != k:   # k's place in the list; those woken after it come after it
        queue += 1
    while queue < count:
        below = involved[queue]
        queue += 1
        cx_lo, cx_hi, cy_lo, cy_hi = reach_block(grid, grid.cell[below], grid.reach[below])
        for cy in range(cy_lo, cy_hi):
            for cx in range(cx_lo, cx_hi):
                j = grid.head[cy * grid.nx + cx]
                while j >= 0:
                    count = _wake_if_on(bodies, env, below, j, t, ux, uy, involved, count, listed)
                    j = grid.next[j]
        for a in range(grid.apart.shape[0]):
            count = _wake_if_on(bodies, env, below, grid.apart[a], t, ux, uy, involved, count, listed)
    return count


@kernel
def _wake_if_on(bodies, env, below, j, t, ux, uy, involved, count, listed):
    """Wake j if it sleeps resting on `below` (touching it, above it); add it to involved."""
    if j == below or not bodies.asleep[j] or listed[j]:
        return count
    dx, dy = bodies.pos[j, 0] - bodies.pos[below, 0], bodies.pos[j, 1] - bodies.pos[below, 1]
    distance = math.sqrt(dx * dx + dy * dy)
    gap = distance - bodies.radius[j] - bodies.radius[below]
    if gap > SLEEP_GAP * min(bodies.radius[j], bodies.radius[below]) or dx * ux + dy * uy <= 0.0:
        return count
    advance(bodies, j, t)   # still frozen: only its reference time moves (woken first, it would fall
    wake(bodies, env, j)    # for all the time it slept)
    listed[j] = True
    involved[count] = j
    return count + 1
