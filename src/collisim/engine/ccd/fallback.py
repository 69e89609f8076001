"""The safety net for frames that need too many events.

Some situations make an exact event-driven simulation process infinitely many
events in a finite time (Zeno behaviour): a pile of inelastic balls at rest
under gravity keeps colliding with ever smaller speeds (inelastic collapse), a
ball on a tilted ramp's corner tries to roll around it. Walls and segment
interiors handle resting on their own (bodies.py); everything else is caught
by the per-frame event budget.

When a frame exceeds its budget, it is finished with one discrete step: every
particle moves in free flight to the frame time, then a few projection passes
push overlapping pairs apart (mass weighted) and out of segments, remove the
approaching part of their normal velocity (as if they came to rest on their
contact), and clamp everything into the box, box last so that nothing is ever
outside it. The event-driven simulation then starts afresh from that state.
Supports are released: resting contacts are found again by the next events.
"""
from numba import njit

from ...geometry.box import centre_range
from ...geometry.circle import line_of_centres
from ...geometry.segment import segment_contact
from ...response.impulse import apply_normal_impulse, push_apart
from .bodies import advance, release
from ...broadphase.cells import assign_all, reach_block

PROJECTION_PASSES = 4


@njit(cache=True, error_model="numpy")
def _separate(bodies, i, j):
    """Push an overlapping pair apart to contact, and stop them approaching."""
    nx, ny, distance = line_of_centres(bodies.pos, i, j)
    overlap = bodies.radius[i] + bodies.radius[j] - distance
    if overlap <= 0.0:
        return
    push_apart(bodies.pos, bodies.mass, i, j, nx, ny, overlap)
    apply_normal_impulse(bodies.vel, bodies.mass, i, j, nx, ny, 0.0)  # e = 0: they stop approaching


@njit(cache=True, error_model="numpy")
def _separate_pairs(bodies, grid):
    for i in range(bodies.radius.shape[0]):
        cx_lo, cx_hi, cy_lo, cy_hi = reach_block(grid, grid.cell[i], grid.reach[i])
        for cy in range(cy_lo, cy_hi):
            for cx in range(cx_lo, cx_hi):
                j = grid.head[cy * grid.nx + cx]
                while j >= 0:
                    if j > i or grid.reach[i] > 1:   # a large body's pairs are found from its side only
                        _separate(bodies, i, j)
                    j = grid.next[j]
        for k in range(grid.apart.shape[0]):   # the large bodies against each other
            j = grid.apart[k]
            if j > i and grid.reach[i] > 1:
                _separate(bodies, i, j)


@njit(cache=True, error_model="numpy")
def _push_out_of_segments(bodies, grid, env):
    for i in range(bodies.radius.shape[0]):
        c = grid.cell[i]
        for k in range(grid.segment_start[c], grid.segment_start[c + 1]):
            nx, ny, distance, qx, qy, _ = segment_contact(bodies.pos[i, 0], bodies.pos[i, 1],
                                                          env.segments[grid.segment_index[k]])
            if distance < bodies.radius[i]:
                bodies.pos[i, 0], bodies.pos[i, 1] = qx + bodies.radius[i] * nx, qy + bodies.radius[i] * ny
                vn = bodies.vel[i, 0] * nx + bodies.vel[i, 1] * ny
                if vn < 0.0:
                    bodies.vel[i, 0] -= vn * nx
                    bodies.vel[i, 1] -= vn * ny


@njit(cache=True, error_model="numpy")
def _keep_inside_box(bodies, env):
    for i in range(bodies.radius.shape[0]):
        for axis in range(2):
            lo, hi = centre_range(env.box, axis, bodies.radius[i])
            if bodies.pos[i, axis] <= lo:
                bodies.pos[i, axis] = lo
                bodies.vel[i, axis] = max(bodies.vel[i, axis], 0.0)
            elif bodies.pos[i, axis] >= hi:
                bodies.pos[i, axis] = hi
                bodies.vel[i, axis] = min(bodies.vel[i, axis], 0.0)


@njit(cache=True, error_model="numpy")
def finish_frame_discretely(bodies, grid, env, t):
    """Bring every particle to time t in free flight, then project the state back
    to a valid one (see the module docstring)."""
    for i in range(bodies.radius.shape[0]):
        advance(bodies, i, t)
        release(bodies, env, i)
    for _ in range(PROJECTION_PASSES):
        assign_all(grid, bodies.pos)
        _separate_pairs(bodies, grid)
        _push_out_of_segments(bodies, grid, env)
        _keep_inside_box(bodies, env)
