"""The safety net for frames that need too many events: one energy-safe discrete step.

Some situations make an exact event-driven simulation process infinitely many
events in a finite time (Zeno behaviour): a pile of inelastic balls at rest
under gravity keeps colliding with ever smaller speeds (inelastic collapse), a
ball on a tilted ramp's corner tries to roll around it. Walls and segment
interiors handle resting on their own (bodies.py); everything else is caught
by the per-frame event budget.

When a frame exceeds its budget, it is finished with one discrete step:

1. every particle moves in free flight to the frame time (each on its own
   parabola, which keeps its kinetic + potential energy: E is measured there);
2. projection passes push overlapping pairs apart (mass weighted), out of
   segments and into the box (box last), and give each contact that is still
   approaching the collision's impulse with the scene's restitution e, adding
   up the energy those impulses dissipate ((1 - e²)/2 · μ u², 0 when e = 1),
   until no overlap is left;
3. the speeds relative to the centre of mass are scaled by one factor so that
   the total energy is E minus what the impulses dissipated: pushing bodies
   apart moved them in the gravity field and the step's contacts are not where
   the exact ones were, and this puts the energy back (to rounding), keeping
   the total momentum.

If the projection cannot remove every overlap in MAX_PASSES passes (JAMMED), or
the positions alone hold more energy than there is (NO_ENERGY: bodies pushed
up by more than their motion can pay for), the step fails and the run stops
with one clear error (stepper.py). The event-driven simulation then starts
afresh from the projected state. Supports are released: resting contacts are
found again by the next events.
"""
import math

import numpy as np
from numba import njit

from ...geometry.box import centre_range
from ...geometry.circle import line_of_centres
from ...geometry.segment import segment_contact
from ...response.impulse import apply_normal_impulse, push_apart
from .bodies import advance, release
from ...broadphase.cells import assign_all, reach_block

MAX_PASSES = 200
# What finish_frame_discretely returns (the frame's value in the run's fallback codes).
FINISHED, JAMMED, NO_ENERGY = 1, 2, 3
# An energy this fraction of the total, or less, is rounding.
ENERGY_TOLERANCE = 1e-13
# An overlap this fraction of the smaller radius, or less, is contact (rounding).
OVERLAP_TOLERANCE = 1e-12


@njit(cache=True, error_model="numpy")
def _separate(bodies, env, i, j):
    """Push an overlapping pair apart to contact and collide it if it approaches. Returns
    (overlapped, energy dissipated)."""
    nx, ny, distance = line_of_centres(bodies.pos, i, j)
    overlap = bodies.radius[i] + bodies.radius[j] - distance
    if overlap <= OVERLAP_TOLERANCE * min(bodies.radius[i], bodies.radius[j]):
        return False, 0.0
    push_apart(bodies.pos, bodies.mass, i, j, nx, ny, overlap)
    reduced = 1.0 / (1.0 / bodies.mass[i] + 1.0 / bodies.mass[j])
    approach = ((bodies.vel[i, 0] - bodies.vel[j, 0]) * nx + (bodies.vel[i, 1] - bodies.vel[j, 1]) * ny)
    apply_normal_impulse(bodies.vel, bodies.mass, i, j, nx, ny, env.restitution)
    return True, _dissipated(reduced, max(approach, 0.0), env.restitution)


@njit(cache=True, error_model="numpy")
def _dissipated(reduced_mass, approach, restitution):
    """Kinetic energy an impact at this approach speed loses."""
    return 0.5 * reduced_mass * (1.0 - restitution * restitution) * approach * approach


@njit(cache=True, error_model="numpy")
def _separate_pairs(bodies, grid, env):
    """One pass over the overlapping pairs: (any overlapped, energy dissipated)."""
    overlapped, lost = False, 0.0
    for i in range(bodies.radius.shape[0]):
        cx_lo, cx_hi, cy_lo, cy_hi = reach_block(grid, grid.cell[i], grid.reach[i])
        for cy in range(cy_lo, cy_hi):
            for cx in range(cx_lo, cx_hi):
                j = grid.head[cy * grid.nx + cx]
                while j >= 0:
                    if j > i or grid.reach[i] > 1:   # a large body's pairs are found from its side only
                        hit, loss = _separate(bodies, env, i, j)
                        overlapped, lost = overlapped or hit, lost + loss
                    j = grid.next[j]
        for k in range(grid.apart.shape[0]):   # the large bodies against each other
            j = grid.apart[k]
            if j > i and grid.reach[i] > 1:
                hit, loss = _separate(bodies, env, i, j)
                overlapped, lost = overlapped or hit, lost + loss
    return overlapped, lost


@njit(cache=True, error_model="numpy")
def _bounce(bodies, env, i, nx, ny):
    """Particle i meets an obstacle whose normal n points at it: its approaching normal
    velocity is reflected with restitution e. Returns the energy dissipated."""
    vn = bodies.vel[i, 0] * nx + bodies.vel[i, 1] * ny
    if vn >= 0.0:
        return 0.0
    bodies.vel[i, 0] -= (1.0 + env.restitution) * vn * nx
    bodies.vel[i, 1] -= (1.0 + env.restitution) * vn * ny
    return _dissipated(bodies.mass[i], -vn, env.restitution)


@njit(cache=True, error_model="numpy")
def _push_out_of_segments(bodies, grid, env):
    overlapped, lost = False, 0.0
    for i in range(bodies.radius.shape[0]):
        c = grid.cell[i]
        apart = grid.reach[i] > 1   # a large body tests every segment
        first, last = (0, env.segments.shape[0]) if apart else (grid.segment_start[c], grid.segment_start[c + 1])
        for k in range(first, last):
            s = k if apart else grid.segment_index[k]
            nx, ny, distance, qx, qy, _ = segment_contact(bodies.pos[i, 0], bodies.pos[i, 1], env.segments[s])
            if distance < bodies.radius[i] * (1.0 - OVERLAP_TOLERANCE):
                bodies.pos[i, 0], bodies.pos[i, 1] = qx + bodies.radius[i] * nx, qy + bodies.radius[i] * ny
                overlapped, lost = True, lost + _bounce(bodies, env, i, nx, ny)
    return overlapped, lost


@njit(cache=True, error_model="numpy")
def _keep_inside_box(bodies, env):
    """Clamp every centre into the box, bouncing those that were outside: (any moved, energy
    dissipated)."""
    moved, lost = False, 0.0
    for i in range(bodies.radius.shape[0]):
        for axis in range(2):
            lo, hi = centre_range(env.box, axis, bodies.radius[i])
            inward = 0.0
            if bodies.pos[i, axis] < lo:
                bodies.pos[i, axis], inward = lo, 1.0
            elif bodies.pos[i, axis] > hi:
                bodies.pos[i, axis], inward = hi, -1.0
            if inward != 0.0:
                moved = True
                lost += _bounce(bodies, env, i, inward if axis == 0 else 0.0, inward if axis == 1 else 0.0)
    return moved, lost


@njit(cache=True, error_model="numpy")
def total_energy(bodies, env):
    """Kinetic + potential energy of the (current) particles; potential -m g·p."""
    energy = 0.0
    for i in range(bodies.radius.shape[0]):
        vx, vy = bodies.vel[i, 0], bodies.vel[i, 1]
        energy += bodies.mass[i] * (0.5 * (vx * vx + vy * vy)
                                    - env.gravity[0] * bodies.pos[i, 0] - env.gravity[1] * bodies.pos[i, 1])
    return energy


@njit(cache=True, error_model="numpy")
def _restore_energy(bodies, env, target):
    """Scale the velocities relative to the centre of mass (or, with no relative motion, the
    velocities) by one factor so that the total energy is target: FINISHED, or NO_ENERGY if
    it cannot be (the positions alone hold more than target, or nothing moves)."""
    n = bodies.radius.shape[0]
    mass, px, py = 0.0, 0.0, 0.0
    for i in range(n):
        mass += bodies.mass[i]
        px += bodies.mass[i] * bodies.vel[i, 0]
        py += bodies.mass[i] * bodies.vel[i, 1]
    ux, uy = px / mass, py / mass
    for _ in range(2):
        motion = 0.0
        for i in range(n):
            dx, dy = bodies.vel[i, 0] - ux, bodies.vel[i, 1] - uy
            motion += 0.5 * bodies.mass[i] * (dx * dx + dy * dy)
        if motion > 0.0:
            break
        ux = uy = 0.0   # one body, or all moving as one: scale the velocities themselves
    wanted = motion + target - total_energy(bodies, env)
    if wanted < 0.0 or (motion == 0.0 and wanted > ENERGY_TOLERANCE * abs(target)):
        return NO_ENERGY
    factor = math.sqrt(wanted / motion) if motion > 0.0 else 0.0
    for i in range(n):
        bodies.vel[i, 0] = ux + factor * (bodies.vel[i, 0] - ux)
        bodies.vel[i, 1] = uy + factor * (bodies.vel[i, 1] - uy)
    return FINISHED


@njit(cache=True, error_model="numpy")
def finish_frame_discretely(bodies, grid, env, t):
    """Bring every particle to time t in free flight, then project the state back to a valid
    one with the energy kept (see the module docstring): FINISHED, JAMMED or NO_ENERGY."""
    for i in range(bodies.radius.shape[0]):
        advance(bodies, i, t)
        release(bodies, env, i)
    energy = total_energy(bodies, env)
    lost = 0.0
    for _ in range(MAX_PASSES):
        assign_all(grid, bodies.pos)
        pairs, lost_pairs = _separate_pairs(bodies, grid, env)
        segments, lost_segments = _push_out_of_segments(bodies, grid, env)
        boxed, lost_box = _keep_inside_box(bodies, env)   # last: nothing ever leaves the box
        lost += lost_pairs + lost_segments + lost_box
        if not (pairs or segments or boxed):   # a pass that moved nothing: no overlap left
            assign_all(grid, bodies.pos)
            return _restore_energy(bodies, env, energy - lost)
    return JAMMED


def failure_message(fallback, budget: int) -> str:
    """The one-line error for a run whose fallback step failed (fallback codes (F,) int8)."""
    frame = int(np.argmax(fallback > FINISHED))
    why = ("bodies stay jammed together" if fallback[frame] == JAMMED else
           "pushing the bodies apart would take more energy than they have")
    return (f"ccd stopped at frame {frame}: it needed more than {budget} events, and its energy-safe "
            f"discrete step cannot finish the frame ({why}); try method discrete or a larger event budget")


FALLBACK_NOTE = ("such frames are finished by one discrete step (free flight, restitution impulses, overlaps "
                 "pushed apart) with the total energy restored by scaling the speeds relative to the centre of "
                 "mass: no overlap, energy kept, positions approximate")
