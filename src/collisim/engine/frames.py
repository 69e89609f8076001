"""A block of frames as a stepper returns it (both methods: discrete.py, ccd/stepper.py)."""
from __future__ import annotations

from collections import namedtuple

import numpy as np

from ..core.arrays import copy_rows, scatter_rows
from ..core.compiling import kernel
from .hierarchy import NOT_COUNTED

Frames = namedtuple("Frames", ["positions", "velocities", "angles", "angular_velocities", "collisions",
                               "candidates", "approximate", "hierarchy"])
Frames.__doc__ = """A block of frames: positions, velocities (f, n, 2); angles, angular_velocities (f, n);
collisions (f, 3) wall, pair, segment in the interval ending at each frame; candidates (f,);
approximate (f,) bool: frames the method could not finish exactly (see Trajectory); hierarchy
(f, 4): the pairs passing each bounding volume level (narrowphase/hierarchy.py), or NOT_COUNTED."""


def new_frames(count: int, n: int, turning: bool = True, into=None) -> Frames:
    """Room for `count` frames of n bodies. Without `turning` the angle arrays have no columns:
    bodies that never turn keep their angles, and storing them every frame would cost as much
    memory traffic as the positions (see constant_angles). into: (positions, velocities), two
    C-contiguous float64 (count, n, 2) arrays to write the state into (a trajectory's own rows:
    simulate.Recorder.views), instead of new ones."""
    columns = n if turning else 0
    positions, velocities = into if into is not None else (np.empty((count, n, 2)), np.empty((count, n, 2)))
    return Frames(positions, velocities, np.empty((count, columns)),
                  np.empty((count, columns)), np.zeros((count, 3), np.int64), np.zeros(count, np.int64),
                  np.zeros(count, np.bool_), np.full((count, 4), NOT_COUNTED, np.int64))


def constant_angles(frames: Frames, angles, angular_velocities) -> Frames:
    """Frames whose angle arrays are read-only views repeating the bodies' constant angles and
    angular velocities (no memory per frame)."""
    count = len(frames.positions)
    return frames._replace(angles=np.broadcast_to(angles, (count, len(angles))),
                           angular_velocities=np.broadcast_to(angular_velocities, (count, len(angles))))


def repeat_idle(frames: Frames, unrecorded: int, fresh: bool) -> Frames:
    """frames whose state from row `unrecorded` on repeats the row before it (a world asleep, none
    of it able to wake: run_frames records that state once). New rows (`fresh`) repeating the
    block's first become read-only views of one row, as constant_angles', so a world asleep costs
    no memory and no copy a frame; rows that are another's (simulate's trajectory) are filled in."""
    count = len(frames.positions)
    if unrecorded >= count:
        return frames
    repeated = {}
    for name in ("positions", "velocities", "angles", "angular_velocities"):
        rows = getattr(frames, name)
        if rows.strides[0] == 0:   # repeats one row already (constant_angles)
            continue
        if fresh and unrecorded == 1:
            repeated[name] = np.broadcast_to(rows[0].copy(), rows.shape)
        else:
            rows[unrecorded:] = rows[unrecorded - 1]
    return frames._replace(**repeated)


@kernel
def record_state(bodies, out, frame, n, order):
    """The bodies' state into out's frame: in the step's order, or in the world's, the step's
    body k as the world's body order[k] (cell_order.py)."""
    b = bodies
    turning = out.angles.shape[1] == n   # bodies that turn (see new_frames)
    if order is None:
        copy_rows(b.positions, out.positions[frame], n)   # (arrays.py: no slice assignment)
        copy_rows(b.velocities, out.velocities[frame], n)
        if turning:
            copy_rows(b.angles, out.angles[frame], n)
            copy_rows(b.angular_velocities, out.angular_velocities[frame], n)
    else:
        scatter_rows(b.positions, out.positions[frame], order)
        scatter_rows(b.velocities, out.velocities[frame], order)
        if turning:
            scatter_rows(b.angles, out.angles[frame], order)
            scatter_rows(b.angular_velocities, out.angular_velocities[frame], order)
