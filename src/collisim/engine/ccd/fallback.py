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
The event-driven simulation then predicts everything afresh from there. With
e < 1 and sleeping on (rest_speed > 0, sleep.py), a storm that fills the budget is usually an accumulation point (inelastic
collapse) that the next frame would run into again: the bodies colliding at
t_last are put to sleep there (sleep.py), which removes their kinetic energy,
a loss the inelastic collisions were making anyway.
"""
from ...compiling import uncounted
from .bodies import advance, fall_asleep

FALLBACK_NOTE = ("such frames skip their last events: every body keeps its exact state at the last event "
                 "processed while the clock jumps to the frame time (no overlap; energy exactly kept when e = 1; up "
                 "to a frame of motion left out; with e < 1 and sleeping on, the bodies colliding at that moment "
                 "are put to sleep, losing their kinetic energy)")


@uncounted
def skip_to_frame(bodies, env, t_last, t_frame):
    """Freeze every particle at its state at t_last (no event is pending before it) and
    make that its state at t_frame. With e < 1 and sleeping on, the bodies that collided at
    t_last are caught at an accumulation point of collisions (the next frame would run into
    it again): they fall asleep there (sleep.py; a hard hit wakes them)."""
    for i in range(bodies.radius.shape[0]):
        advance(bodies, i, t_last)
        bodies.t_ref[i] = t_frame
        if env.restitution < 1.0 and env.rest_speed[i] > 0.0 and bodies.last_hit[i] == t_last:
            fall_asleep(bodies, i)
