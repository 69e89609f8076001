"""A block of frames of a world asleep, without calling the step.

Once every body sleeps and none has moved since the contacts were found, nothing can move or
wake (no body is awake to come near a sleeper): run_frames then only logs the support the
sleepers rest on, once a step, and records the same state every frame. A block that starts so
is made here in numpy, to the same bytes: Box2D's empty awake set costs nothing, and handing the
compiled step its some hundred arrays costs more than the block's whole work.
"""
import time

import numpy as np

from ..core.kinds import SUPPORT
from ..model.trajectory import Events
from .frames import Frames


def idle_block(count: int, first_step: int, steps: int, dt: float, carried: np.ndarray, state: tuple,
               candidates: int, hierarchy: np.ndarray, into) -> tuple:
    """(Frames, Events) of `count` frames of `steps` steps of dt, from step number first_step, of a
    world asleep. carried (k, 5): the support each sleeper gives (body, static, impulse, x, y),
    logged at every step as islands.log_carried logs it; state: (positions, velocities, angles,
    angular_velocities) as recorded, kept by the caller; candidates and hierarchy (4,): the frame's counts, unchanged.
    into: (positions, velocities) rows to fill, else the state is one row repeated (read-only)."""
    frames = Frames(*(np.broadcast_to(row, (count,) + row.shape) for row in state),
                    np.zeros((count, 3), np.int64), np.full(count, candidates, np.int64),
                    np.zeros(count, np.bool_), np.tile(hierarchy, (count, 1)))
    if into is not None:
        into[0][:], into[1][:] = state[0], state[1]
        frames = frames._replace(positions=into[0], velocities=into[1])
    return frames, support_events(first_step, steps, dt, carried)


def support_events(first_step: int, steps: int, dt: float, carried: np.ndarray) -> Events:
    """The carried supports at each of `steps` steps, in canonical order: the steps in turn, and
    within a step the supports by (body, static), ties as carried (a stable sort)."""
    body, static = carried[:, 0].astype(np.intp), carried[:, 1].astype(np.intp)
    order = np.lexsort((static, body))
    k = len(order)
    times = np.arange(first_step, first_step + steps, dtype=np.int64) * dt   # (as log_carried: step · dt)
    return Events(np.repeat(times, k), np.full(k * steps, SUPPORT, np.int8), np.tile(body[order], steps),
                  np.tile(static[order], steps), np.tile(carried[order, 2], steps),
                  np.tile(carried[order, 3:5], (steps, 1)))


def timed_idle(profile, make):
    """make()'s result, its seconds added to the profile's sleeping phase."""
    start = time.perf_counter()
    result = make()
    profile.add("sleep", time.perf_counter() - start)
    return result
