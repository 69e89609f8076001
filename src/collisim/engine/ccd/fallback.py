"""The safety net for frames that need too many events: the rest of the frame is skipped.

Some situations make an exact event-driven simulation process infinitely many
events in a finite time (Zeno behaviour): a pile of inelastic balls keeps
colliding with ever smaller speeds (inelastic collapse), a ball on a tilted
ramp's corner tries to roll around it. Walls and segment interiors handle
resting on their own (bodies.py), sleeping handles bodies held still by others
(sleep.py); anything left is caught by the per-frame event budget.

When a frame exceeds its budget, the events after the last one processed are
not simulated: every body keeps its exact state at that last event time t_last,
and the clock jumps to the frame time (the bodies are frozen for t_frame -
t_last, at most one frame). The state is the exact one of t_last, so nothing
overlaps, nothing leaves the box and kinetic + potential energy is exactly what
it was: nothing is lost but time, which the frame's flag in
Trajectory.approximate records. (A discrete step that moves everything to the
frame time and pushes overlaps apart cannot keep the energy: the pushes do work
against gravity, and in a pile at rest there is no motion left to pay for it.)
The event-driven simulation then predicts everything afresh from there.

With e < 1 and sleeping on (rest_speed > 0, sleep.py), a storm that fills the budget is
usually an accumulation point (inelastic collapse), or a ball squeezed in a row on the floor
that the bodies still bouncing above keep hitting awake. So first, once a frame, the storm is
frozen instead (freeze_storm): the bodies colliding at t_last and every awake body in the block
of cells around each fall asleep there, losing their kinetic energy (a loss the inelastic
collisions were making anyway), and cannot be woken before the frame time; the rest of the
frame goes on with a new budget, the bodies elsewhere exactly as without the storm. Skipping
the whole frame instead held the bodies above up with it, frame after frame, so that they never
settled and the storm came back every frame to the end of the run (one 200-ball pile in 36,
benchmarks/ccd_settling.py). Only when the frame runs out of its second budget too is the rest
of it skipped, as above, and the bodies colliding at t_last put to sleep.
"""
import math

from ...core.compiling import kernel
from ...broadphase.cells import reach_block
from .bodies import advance, fall_asleep

FALLBACK_NOTE = ("with e < 1 and sleeping on, the bodies caught in the storm and those around them are first put to "
                 "sleep where they are, losing their kinetic energy, and the frame goes on without them; a frame over "
                 "the budget again (or any, with e = 1 or sleeping off) skips its last events: every body keeps its "
                 "exact state at the last event processed while the clock jumps to the frame time (no overlap; "
                 "energy exactly kept when e = 1; up to a frame of motion left out)")


@kernel
def caught_in_storm(bodies, env, i, t_last):
    """Was body i caught in the storm that ran a frame over its budget: did it collide at the
    last event processed, t_last, where it may fall asleep (e < 1, sleeping on)?"""
    return env.restitution < 1.0 and env.rest_speed[i] > 0.0 and bodies.last_hit[i] == t_last


@kernel
def skip_to_frame(bodies, env, t_last, t_frame):
    """Freeze every particle at its state at t_last (no event is pending before it) and
    make that its state at t_frame. With e < 1 and sleeping on, the bodies that collided at
    t_last are caught at an accumulation point of collisions (the next frame would run into
    it again): they fall asleep there (sleep.py; a hard hit wakes them)."""
    for i in range(bodies.radius.shape[0]):
        advance(bodies, i, t_last)
        bodies.t_ref[i] = t_frame
        if caught_in_storm(bodies, env, i, t_last):
            fall_asleep(bodies, i)


@kernel
def freeze_storm(bodies, grid, env, t_last, frozen, rest_speeds):
    """At a frame's budget, with sleeping on: the bodies that collided at t_last (the storm's)
    and every awake body in the block of cells around each fall asleep at t_last, and stay
    asleep, whatever hits them, until the frame time (thaw): their rest speeds are set to inf
    meanwhile, the old ones kept in rest_speeds. So the rest of the frame goes on with them as
    fixed obstacles: a storm is a row squeezed on the floor that the bodies still bouncing above
    hit awake again, and skipping the whole frame (skip_to_frame) would hold those up too, frame
    after frame, so that they never settle. Fills frozen with the bodies (the caller predicts
    them again) and returns their number."""
    count = 0
    for i in range(bodies.radius.shape[0]):
        if caught_in_storm(bodies, env, i, t_last) and not bodies.asleep[i]:
            count = _freeze(bodies, env, i, t_last, frozen, count, rest_speeds)
    caught = count
    for k in range(caught):
        cx_lo, cx_hi, cy_lo, cy_hi = reach_block(grid, grid.cell[frozen[k]], grid.reach[frozen[k]])
        for cy in range(cy_lo, cy_hi):
            for cx in range(cx_lo, cx_hi):
                j = grid.head[cy * grid.nx + cx]
                while j >= 0:
                    if not bodies.asleep[j] and env.rest_speed[j] > 0.0:
                        count = _freeze(bodies, env, j, t_last, frozen, count, rest_speeds)
                    j = grid.next[j]
    return count


@kernel
def _freeze(bodies, env, i, t, frozen, count, rest_speeds):
    advance(bodies, i, t)
    fall_asleep(bodies, i)
    rest_speeds[count] = env.rest_speed[i]
    env.rest_speed[i] = math.inf
    frozen[count] = i
    return count + 1


@kernel
def thaw(env, frozen, count, rest_speeds):
    """Give the bodies freeze_storm froze their rest speeds back (they may be woken again)."""
    for k in range(count):
        env.rest_speed[frozen[k]] = rest_speeds[k]
