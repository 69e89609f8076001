"""Compiling the discrete step's kernels from the far end, for a second process on a first run.

numba compiles one kernel at a time in a process, and compiles a kernel's callees as it types
the kernel, in the order its source calls them: `run_frames` (discrete.py) first compiles its
contact phases, then the solver, the integration and the statics. A second process that
compiles the later kernels for the same world while the first works through the earlier ones
saves them into the kernel cache (core/compiling.py: processes compile side by side and take
turns to save), where the first finds them when it gets there and loads them instead.

`compile_step_tail` compiles each of those kernels as compiled code calls it
(core/compiling.compile_for_compiled_code) for the types of the stepper's own state, as
run_frames hands it, with no contact rows (count 0) (tests/test_warm.py checks that the run
compiles none of them again). The calls are in the reverse of run_frames' order, so the two processes meet in
the middle.
"""
from __future__ import annotations

import numpy as np

from ..core.compiling import compile_for_compiled_code
from ..response.rows import new_rows
from ..response.solver import add_contact_motion, collide, come_to_rest, solve_positions, solve_velocities
from ..response.warmstart import recall, remember
from .discrete import DiscreteStepper, _log_contacts
from .eventlog import new_log
from .integrate import integrate
from .statics_paths import map_number, mark_held, statics_phase, statics_scratch


def step_tail_calls(world, fps: float, substeps: int = 1, broadphase: str = "auto") -> list:
    """The kernels run_frames calls after its contact phase, each with arguments of the types it
    hands them (a stepper's own state, which the calls may change), in the reverse of its
    order: [(kernel, arguments)]."""
    stepper = DiscreteStepper(world, fps, substeps, broadphase)
    b, s, w, dt = stepper.bodies, stepper.statics, stepper.work, stepper.dt
    n, rows, none = len(b.positions), new_rows(4), np.int64(0)
    the_map = map_number(s.segments)
    scratch = statics_scratch(n, s.segments.shape[0])
    log, now, collisions = new_log(4), 0.0, np.zeros(3, np.int64)
    v, turn, m, inertia = b.velocities, b.angular_velocities, w.inverse_masses, w.inverse_inertias
    return [
        (statics_phase, (b, s, scratch, dt, log, now, collisions)),
        (mark_held, (rows, none, scratch[3], the_map)),
        (remember, (rows, none, n, the_map + 1)),
        (_log_contacts, (rows, none, log, now, collisions, the_map)),
        (come_to_rest, (rows, none, v, turn, m, inertia, s.friction)),
        (add_contact_motion, (b, rows, none, w.push, w.push_turn, w.shift, w.shift_turn, dt, w.moved)),
        (integrate, (b.positions, v, b.accelerations, b.angles, turn, dt, s.keep)),
        (solve_positions, (rows, none, v, turn, b.accelerations, m, inertia, dt, s.iterations, w.push, w.push_turn,
                           w.shift, w.shift_turn, s.pulled)),
        (solve_velocities, (rows, none, v, turn, b.accelerations, m, inertia, s.friction, dt, s.iterations, w.push,
                            w.push_turn, s.pulled)),
        (recall, (rows, none, stepper.memory, n, the_map + 1)),
        (collide, (rows, none, v, turn, b.accelerations, m, inertia, s.restitution, s.friction, s.rest_speed, dt,
                   s.iterations)),
    ]


def compile_step_tail(world, fps: float, substeps: int = 1, broadphase: str = "auto") -> None:
    """Compile (or load from the cache) the kernels of step_tail_calls, in its order."""
    for kernel, arguments in step_tail_calls(world, fps, substeps, broadphase):
        compile_for_compiled_code(kernel, arguments)
