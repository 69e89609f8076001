"""Collision response: the impulses of the contacts that happen at one instant.

A contact k is between particle i and either particle j or an infinitely heavy
obstacle (a box wall, a segment). n_k is the unit normal from i towards the
other body and u_k = (v_i - v_j)·n_k the speed at which they approach. An
impulse P_k >= 0 along n_k changes v_i by -P_k/m_i n_k and v_j by +P_k/m_j n_k.

Newton's law of restitution asks the approach speed after the collision to be
-e times the approach speed before. For one contact this gives the textbook
formula P = (1 + e) m_i m_j / (m_i + m_j) u (m_j = inf for an obstacle: the
normal velocity is reflected, v_n -> -e v_n); it conserves momentum for any e
and kinetic energy for e = 1.

Resting on another particle, or on a segment's end point, is beyond an
event-driven method (it needs a continuous contact force): an inelastic ball
on a ball that rests on the floor would bounce infinitely often in a finite
time (Zeno), and so would a pile (inelastic collapse). Two rules keep the
number of events finite, at the scale of a micro-bounce that rises
MIN_BOUNCE_HEIGHT × the radius under gravity (invisible):

* a contact that gravity presses together (one side resting on a support)
  always rebounds at least with the micro-bounce speed;
* collisions slower than the micro-bounce speed are elastic (as for real
  materials, e -> 1 as the impact speed -> 0).

Walls and segment interiors carry resting particles instead (bodies.py), and
particles held still by their supports fall asleep (sleep.py): a sleeping particle
is a fixed obstacle, like a wall, until a hit wakes it.

Luding and McNamara's TC model, against inelastic collapse: a contact between two particles
either of which collided less than Environment.tc ago is elastic (e = 1), and so is a contact
with a wall or segment of a particle that collided with another less than tc ago (a ball
rattling between the floor and the body above it); tc = 0 turns it off. A particle that only
meets walls and segments keeps e (a ball settling into a vee, hitting each side ever sooner
after the other, would otherwise bounce there for ever). By default
(default_tc) tc is TC_SHARE of the time gravity takes to give a body its rest speed (sleep.py),
about 1e-4 s for a ball of radius 0.5 under 9.81, and 0 wherever bodies never sleep (no gravity,
or e = 1), so gases run exactly as without it. In a 200-ball pile dropped with e = 0, balls
pressed together against a side wall collapsed: one took 13 000 collisions in a frame, and 8
frames of each pile (seeds 1 and 2) ran out of their event budget, in 29-31 s of compute; with
the default tc none does (benchmarks/ccd_settling.py pile). With the model between particles
only, 2 frames each still did: the ball was squeezed between a neighbour and the wall.

Several contacts can happen at exactly the same time (symmetric set-ups: a ball
hit from two mirrored sides, a billiard break). Solving them one after the
other would favour whichever comes first; instead all contacts of one instant
are solved together, by projected Gauss-Seidel: sweep over the contacts,
correcting each impulse to meet its restitution target given the others, never
letting an impulse become negative (contacts push, they never pull), until the
corrections vanish. The result does not depend on the order of the sweep (the
solution is unique), so mirror-symmetric collisions stay mirror symmetric. With
e = 1 the converged impulses do no net work: energy is conserved. A single
contact is exact after the first sweep.
"""
import math
from collections import namedtuple

import numpy as np

from ...core.compiling import constructor, kernel
from ...core.geometry.box import wall_geometry
from ...core.geometry.circle import line_of_centres
from ...core.geometry.segment import segment_contact
from ...core.kinds import N_WALLS, PAIR, SEGMENT, WALL
from .bodies import comes_to_rest, keep_or_release, rest_on

TC_SHARE = 0.01   # the default tc: this share of the time gravity takes to reach the rest speed


def default_tc(gravity, rest_speed) -> float:
    """The TC model's time when the scene does not state one: TC_SHARE x the smallest positive rest
    speed (n,) / |g|, or 0 when no body sleeps (no gravity, e = 1, rest speed 0)."""
    pull = math.hypot(gravity[0], gravity[1])
    resting = np.asarray(rest_speed, np.float64)
    resting = resting[resting > 0.0]
    if pull == 0.0 or resting.size == 0:
        return 0.0
    return TC_SHARE * float(resting.min()) / pull


Contacts = namedtuple("Contacts", ["kind", "i", "j", "other", "nx", "ny", "approach", "rebound", "impulse",
                                   "x", "y", "can_rest", "count"])
Contacts.__doc__ = """Up to c contacts of one instant, each (c,) array: kind (WALL, PAIR, SEGMENT); i the
particle; j the other particle or -1; other the event's other index (wall, particle or segment);
nx, ny the normal from i towards the other body; approach the approach speed before; rebound
the separation speed asked for after; impulse; x, y the contact point; can_rest: may i come to
rest on this obstacle. count (1,) int64."""

# The micro-bounce: rising this fraction of the (smaller) radius under gravity.
MIN_BOUNCE_HEIGHT = 1e-4

# Gauss-Seidel sweeps stop when no impulse changes a velocity by more than this
# fraction of the largest speed involved, or after MAX_SWEEPS (slowly converging
# groups: long chains of simultaneous contacts).
SWEEP_TOLERANCE = 1e-15
MAX_SWEEPS = 100

# Every contact leaves separating at least this fraction of the largest speed involved. A
# target of exactly 0 (e = 0, or a rebound below rounding) can leave the pair approaching by
# a rounding error that no impulse can fix (the change is below the velocities' last digit),
# and it would collide again at the same instant for ever.
SEPARATION_FLOOR = 1e-12


@constructor(error_model="numpy")
def new_contacts(capacity):
    """Room for `capacity` simultaneous contacts."""
    return Contacts(np.empty(capacity, np.int64), np.empty(capacity, np.int64), np.empty(capacity, np.int64),
                    np.empty(capacity, np.int64), np.empty(capacity), np.empty(capacity), np.empty(capacity),
                    np.empty(capacity), np.empty(capacity), np.empty(capacity), np.empty(capacity),
                    np.empty(capacity, np.bool_), np.zeros(1, np.int64))


@kernel
def _rebound_speed(env, approach, pressing, radius, can_rest, restitution):
    """The separation speed a contact should have after the collision (module docstring)."""
    if can_rest:
        return restitution * approach
    gravity = math.hypot(env.gravity[0], env.gravity[1])
    micro = math.sqrt(2.0 * gravity * MIN_BOUNCE_HEIGHT * radius)
    rebound = approach if approach < micro else restitution * approach
    if pressing > 0.0:
        rebound = max(rebound, math.sqrt(2.0 * pressing * MIN_BOUNCE_HEIGHT * radius))
    return rebound


@kernel
def _add(bodies, env, contacts, kind, i, j, other, nx, ny, x, y, can_rest):
    """Append a contact of particle i (current, with its acceleration before the contact)."""
    k = contacts.count[0]
    vx, vy = bodies.vel[i, 0], bodies.vel[i, 1]
    ax, ay = bodies.acc[i, 0], bodies.acc[i, 1]
    radius = bodies.radius[i]
    if j >= 0:
        vx, vy = vx - bodies.vel[j, 0], vy - bodies.vel[j, 1]
        ax, ay = ax - bodies.acc[j, 0], ay - bodies.acc[j, 1]
        radius = min(radius, bodies.radius[j])
    approach = max(vx * nx + vy * ny, 0.0)
    # TC model (see the module): two bodies, either hit within tc before, collide elastically; a
    # body and a wall or segment only if the body was hit by another within tc before
    t = bodies.t_ref[i]
    # read unconditionally (j = -1 reads the last body's, unused)
    hit_i, hit_j, paired_i = bodies.last_hit[i], bodies.last_hit[j], bodies.last_pair_hit[i]
    if kind == PAIR:
        recent = t - hit_i < env.tc or (j >= 0 and t - hit_j < env.tc)
    else:
        recent = t - paired_i < env.tc
    restitution = 1.0 if recent else env.restitution
    contacts.kind[k], contacts.i[k], contacts.j[k], contacts.other[k] = kind, i, j, other
    contacts.nx[k], contacts.ny[k], contacts.x[k], contacts.y[k] = nx, ny, x, y
    contacts.approach[k] = approach
    contacts.rebound[k] = _rebound_speed(env, approach, ax * nx + ay * ny, radius, can_rest, restitution)
    contacts.impulse[k] = 0.0
    contacts.can_rest[k] = can_rest
    contacts.count[0] = k + 1


@kernel
def add_wall_contact(bodies, env, contacts, i, wall):
    """Particle i (current) touches box wall `wall`; it is put exactly on the wall."""
    radius = bodies.radius[i]
    axis, bound, inward = wall_geometry(env.box, wall, radius)
    bodies.pos[i, axis] = bound
    nx, ny = (-inward, 0.0) if axis == 0 else (0.0, -inward)
    x, y = bodies.pos[i, 0] + radius * nx, bodies.pos[i, 1] + radius * ny
    _add(bodies, env, contacts, WALL, i, -1, wall, nx, ny, x, y, True)


@kernel
def add_segment_contact(bodies, env, contacts, i, s):
    """Particle i (current) touches segment s; it is put exactly at contact distance."""
    nx, ny, _, qx, qy, u = segment_contact(bodies.pos[i, 0], bodies.pos[i, 1], env.segments[s])
    bodies.pos[i, 0], bodies.pos[i, 1] = qx + bodies.radius[i] * nx, qy + bodies.radius[i] * ny
    # Only the interior can carry a resting particle: on an end cap it would roll off.
    _add(bodies, env, contacts, SEGMENT, i, -1, s, -nx, -ny, qx, qy, 0.0 < u < 1.0)


@kernel
def add_pair_contact(bodies, env, contacts, i, j):
    """Particles i and j (current) touch. One asleep (sleep.py) is a fixed obstacle for the
    other: the contact is the awake one's, with j = -1 and `other` the sleeper."""
    if bodies.asleep[i]:
        i, j = j, i
    nx, ny, _ = line_of_centres(bodies.pos, i, j)
    radius = bodies.radius[i]
    _add(bodies, env, contacts, PAIR, i, -1 if bodies.asleep[j] else j, j, nx, ny, bodies.pos[i, 0] + radius * nx,
         bodies.pos[i, 1] + radius * ny, False)


@kernel
def mark_hits(bodies, contacts, t):
    """Remember t as the last collision of every body a contact of this instant pushed."""
    for k in range(contacts.count[0]):
        if contacts.impulse[k] > 0.0:
            bodies.last_hit[contacts.i[k]] = t
            if contacts.kind[k] == PAIR:
                bodies.last_pair_hit[contacts.i[k]] = t
            if contacts.j[k] >= 0:
                bodies.last_hit[contacts.j[k]] = t
                bodies.last_pair_hit[contacts.j[k]] = t


@kernel
def _apply(bodies, contacts, k, change):
    """Add `change` to contact k's impulse, updating the velocities."""
    i, j = contacts.i[k], contacts.j[k]
    nx, ny = contacts.nx[k], contacts.ny[k]
    # j first, then i: i != j, so the order changes no number
    if j >= 0:
        bodies.vel[j, 0] += change / bodies.mass[j] * nx
        bodies.vel[j, 1] += change / bodies.mass[j] * ny
    bodies.vel[i, 0] -= change / bodies.mass[i] * nx
    bodies.vel[i, 1] -= change / bodies.mass[i] * ny
    contacts.impulse[k] += change


@kernel
def solve_contacts(bodies, contacts):
    """Impulses for all contacts at once (projected Gauss-Seidel, see module docstring)."""
    count = contacts.count[0]
    scale = 0.0
    for k in range(count):
        i, j = contacts.i[k], contacts.j[k]
        scale = max(scale, contacts.approach[k], abs(bodies.vel[i, 0]), abs(bodies.vel[i, 1]))
        if j >= 0:
            scale = max(scale, abs(bodies.vel[j, 0]), abs(bodies.vel[j, 1]))
    for _ in range(MAX_SWEEPS):
        largest = 0.0
        for k in range(count):
            i, j = contacts.i[k], contacts.j[k]
            vx, vy = bodies.vel[i, 0], bodies.vel[i, 1]
            inverse_mass = 1.0 / bodies.mass[i]
            if j >= 0:
                vx, vy = vx - bodies.vel[j, 0], vy - bodies.vel[j, 1]
                inverse_mass += 1.0 / bodies.mass[j]
            approach = vx * contacts.nx[k] + vy * contacts.ny[k]
            target = -max(contacts.rebound[k], SEPARATION_FLOOR * scale)
            change = max(contacts.impulse[k] + (approach - target) / inverse_mass, 0.0) - contacts.impulse[k]
            _apply(bodies, contacts, k, change)
            largest = max(largest, abs(change) * inverse_mass)
        if largest <= SWEEP_TOLERANCE * scale:
            return


@kernel
def settle_resting(bodies, env, contacts):
    """After a collision with an obstacle, a resting particle may leave its support; and a
    particle that leaves a wall or segment too slowly to matter rests on it instead."""
    for k in range(contacts.count[0]):
        i = contacts.i[k]
        if contacts.j[k] < 0:
            keep_or_release(bodies, env, i)
        if not contacts.can_rest[k]:
            continue
        nx, ny = -contacts.nx[k], -contacts.ny[k]  # from the obstacle towards the particle
        rebound = bodies.vel[i, 0] * nx + bodies.vel[i, 1] * ny
        if comes_to_rest(env, bodies.radius[i], rebound, nx, ny):
            support = contacts.other[k] if contacts.kind[k] == WALL else N_WALLS + contacts.other[k]
            rest_on(bodies, env, i, support, nx, ny)
            # the rebound it would have had is not given: the support pushed that much less
            contacts.impulse[k] -= bodies.mass[i] * max(rebound, 0.0)
