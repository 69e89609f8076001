"""Compiling the discrete step's kernels from the far end, for a second process on a first run.

numba compiles one kernel at a time in a process, and compiles a kernel's callees as it types
the kernel, in the order its source calls them: `run_frames` (discrete.py) first compiles its
contact phase (from its start: the broad phase, the pairs' rows, the walls' and the segments'),
then the solver (the soft step or the rigid solve: response/solve.py), the integration, the
statics and the sleepers'. A second process that compiles these from the far end for the same
world, while the first works through them from the start, saves them into the kernel cache
(core/compiling.py: processes compile side by side and take turns to save), where the first
finds them when it gets there and loads them instead; the two meet in the middle.

`compile_far_end` compiles each kernel as compiled code calls it
(core/compiling.compile_for_compiled_code), for the types of a stepper's own state with no
contact rows (count 0): the types run_frames hands it (tests/test_warm.py checks that the run
compiles none of them again).
"""
from __future__ import annotations

import numpy as np

from ..core.arrays import copy_rows
from ..core.compiling import compile_for_compiled_code
from ..response.pair_rows import pair_manifolds
from ..response.rows import near_segments, new_found, new_rows, rows_from, segment_manifolds, wall_manifolds
from ..response.solve import hold_contacts, rest_contacts
from ..response.solver import add_contact_motion, collide
from ..response.warmstart import recall, remember
from .discrete import DiscreteStepper, _log_contacts
from .eventlog import into_canonical_order, new_log
from .fast_polygons import fly, pair_outpaced
from .frames import new_frames
from .hierarchy import count_placed
from .integrate import integrate
from .islands import fall_asleep, keep_sleepers, log_carried, sleepers_touching, wake_near
from .statics_paths import map_number, mark_held, statics_phase, statics_scratch


def far_end_calls(world, fps: float, substeps: int = 1, broadphase: str = "auto", rest_speed=None) -> list:
    """The kernels of run_frames' far end, each with arguments of the types run_frames hands them
    (a stepper's own state, which the calls may change), in the reverse of the order it compiles
    them: the frame's record, the sleepers' (a world that may sleep), the statics (with the
    swept polygons' flight), the solver and the integration, then the contact phase's from its
    end: [(kernel, arguments)]."""
    stepper = DiscreteStepper(world, fps, substeps, broadphase, rest_speed=rest_speed)
    b, s, w, dt, sleep = stepper.bodies, stepper.statics, stepper.work, stepper.dt, stepper.sleep
    n, rows, none = len(b.positions), new_rows(4), np.int64(0)
    the_map = map_number(s.segments)
    scratch = statics_scratch(n, s.segments.shape[0])
    log, now, collisions = new_log(4), 0.0, np.zeros(3, np.int64)
    v, turn, m, inertia = b.velocities, b.angular_velocities, w.inverse_masses, w.inverse_inertias
    memory = stepper.memory
    found, pairs, flags = new_found(4), np.empty((0, 2), np.int64), np.zeros(n, np.bool_)
    no_touching = np.zeros(0, np.bool_)   # which of the (no) pairs touch
    out = new_frames(1, n)   # a frame's rows, as run_frames records them
    recording = [(into_canonical_order, (log,)), (copy_rows, (b.positions, out.positions[0], n)),
                 (copy_rows, (b.angles, out.angles[0], n)), (copy_rows, (w.recorded, out.hierarchy[0], 4))]
    if w.levels is not None:   # the bounding-volume funnel of a world with polygons (hierarchy.py)
        recording.append((count_placed, (b, pairs, w.vertices, *w.levels, no_touching, out.hierarchy[0])))
    polygons = [] if s.volumes is None else [   # the fast polygons' flight, and their check (fast_polygons.py)
        (fly, (b, none, w.fast.start[0], s.box, s.restitution, s.friction, s.rest_speed, s.keep, dt, log, now,
               out.collisions[0])),
    ]
    outpacing = [] if s.volumes is None else [(pair_outpaced, (b, w.margin, dt, sleep.asleep))]
    on_segments = [] if s.volumes is None or s.index is None else [   # polygons near segments
        (segment_manifolds, (b, w.vertices, w.margin, s.segments, found, none, s.volumes, sleep.asleep))]
    near = [] if not on_segments else [(near_segments, (b, w.margin, s.segments))]
    sleeping = [] if sleep.on is None else [
        (fall_asleep, (sleep, b, rows, none, dt)),
        (keep_sleepers, (sleep, memory, memory, n, the_map + 1)),
        (log_carried, (sleep, log, none, none, dt)),
    ]
    contact_sleeping = [] if sleep.on is None else [
        (sleepers_touching, (sleep, b, w.vertices, pairs, no_touching, pairs, no_touching, s.volumes)),
        (wake_near, (sleep, b, w.vertices, w.margin, pairs, s.volumes)),
    ]
    return recording + sleeping + [
        (statics_phase, (b, s, scratch, dt, log, now, collisions)),
    ] + polygons + [
        (mark_held, (rows, none, scratch[3], the_map)),
        (remember, (rows, none, n, the_map + 1)),
        (_log_contacts, (rows, none, log, now, collisions, the_map)),
        (rest_contacts, (s.rigid, rows, none, v, turn, m, inertia, s.friction)),
        (add_contact_motion, (b, rows, none, w.push, w.push_turn, w.shift, w.shift_turn, dt, w.moved)),
        (integrate, (b.positions, v, b.accelerations, b.angles, turn, dt, s.keep)),
        (hold_contacts, (s.soft, s.rigid, rows, none, b.radii, v, turn, b.accelerations, m, inertia, s.friction, dt,
                         s.iterations, s.keep, s.pulled, w.push, w.push_turn, w.shift, w.shift_turn, w.moved)),
        (recall, (rows, none, memory, n, the_map + 1)),
        (collide, (rows, none, v, turn, b.accelerations, m, inertia, s.restitution, s.friction, s.rest_speed, dt,
                   s.iterations)),
    ] + outpacing + [
        (rows_from, (found, none, b, rows)),
    ] + on_segments + [
        (wall_manifolds, (b, w.vertices, w.margin, dt, s.box, s.rest_speed, flags, found, none, s.volumes,
                          sleep.asleep)),
    ] + contact_sleeping + [
        (pair_manifolds, (b, w.vertices, w.margin, dt, pairs, found, none, flags, no_touching, s.volumes,
                          sleep.asleep, flags)),
    ] + near


def compile_far_end(world, fps: float, substeps: int = 1, broadphase: str = "auto", rest_speed=None) -> None:
    """Compile (or load from the cache) the kernels of far_end_calls, in its order."""
    for kernel, arguments in far_end_calls(world, fps, substeps, broadphase, rest_speed):
        compile_for_compiled_code(kernel, arguments)
