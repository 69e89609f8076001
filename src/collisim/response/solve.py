"""Which contact solver holds a world's resting contacts: the soft step or the rigid solve.

Impacts are Newton's either way (solver.collide). What rests is held

* by the soft step (soft_step.py) in a world with polygons under gravity whose masses are
  comparable: stacks and pyramids of boxes, which its substeps carry better than one rigid solve
  can (a pyramid of 5 050 boxes stands under it and falls under the rigid solve:
  benchmarks/pyramid_stands.py);
* by the rigid solve (solver.py) elsewhere: a gas, where nothing rests; a world of circles alone,
  whose elastic bounces under gravity it keeps exact (the soft step's springs and relax lost
  half the energy of `collisim bench accuracy`'s gravity_bounce at 16 substeps, where the rigid
  solve keeps it to rounding) and whose columns it holds without the springs' give; and a world
  of very unequal masses, where a heavy body on light ones needs the rigid solve's hold from
  below (hold.py): under the soft step's springs a ball 1000 times heavier than the one under
  it sank 8 % of a radius into it, and one 10⁶ times heavier sank through.

The choice is made once a run (`solver_of`) and handed to the step as two flags, soft and rigid,
one True and the other None (`flags_of`): numba leaves out a branch on `flag is not None` only
where the flag is typed None, so the compiled step holds only the solver its world uses.
"""
import numpy as np

from ..core.compiling import compiled
from ..core.kinds import CIRCLE
from .soft_step import soft_step
from .solver import come_to_rest, solve_positions, solve_velocities

RIGID, SOFT = "rigid", "soft"
SOFT_MASS_RATIO = 10.0   # the soft step holds bodies up to this many times heavier than others


def solver_of(world) -> str:
    """SOFT or RIGID, for a World (see the module)."""
    if world.n == 0 or not np.any(world.accelerations != 0.0) or np.all(world.shapes == CIRCLE):
        return RIGID
    masses = world.masses
    return SOFT if masses.max() <= SOFT_MASS_RATIO * masses.min() else RIGID


def flags_of(solver: str) -> tuple:
    """(soft, rigid): True for the solver named, None for the other."""
    return (True, None) if solver == SOFT else (None, True)


@compiled
def hold_contacts(soft, rigid, rows, count, radii, lin, ang, accelerations, inverse_masses, inverse_inertias,
                  friction, dt, iterations, keep, pulled, push_lin, push_ang, shift_lin, shift_ang, moved):
    """The contacts' share of the step, as push and shift (solver.add_contact_motion), by the soft
    step or the rigid solve's velocities and positions (flags_of). Returns the number of rows the
    rigid solve held from below (hold.py), 0 under the soft step."""
    if soft is not None:
        soft_step(rows, count, radii, lin, ang, accelerations, inverse_masses, inverse_inertias, friction, dt, keep,
                  push_lin, push_ang, shift_lin, shift_ang, moved)
    if rigid is None:
        return 0
    held = solve_velocities(rows, count, lin, ang, accelerations, inverse_masses, inverse_inertias, friction, dt,
                            iterations, push_lin, push_ang, pulled)
    return held + solve_positions(rows, count, lin, ang, accelerations, inverse_masses, inverse_inertias, dt,
                                  iterations, push_lin, push_ang, shift_lin, shift_ang, pulled)


@compiled
def rest_contacts(rigid, rows, count, lin, ang, inverse_masses, inverse_inertias, friction):
    """After the integration, the rigid solve's rest pass (solver.come_to_rest); the soft step's
    relax has done its work already."""
    if rigid is not None:
        come_to_rest(rows, count, lin, ang, inverse_masses, inverse_inertias, friction)
