"""Run a scene: stream the trajectory in blocks of frames, or collect it whole."""
from __future__ import annotations

import warnings
from typing import Iterator

import numpy as np

from ..interrupts import ctrl_c_safe
from ..model.scene import Scene
from ..model.trajectory import MAX_EVENTS, Events, Trajectory, approximate_summary
from .hierarchy import world_counts
from .ccd.stepper import CCDStepper
from .discrete import DiscreteStepper
from .frames import Frames
from .start import check_scene

# The methods, by the name a scene gives: each builds a stepper with run(count) -> (Frames, Events).
METHODS = {
    "discrete": lambda scene: DiscreteStepper(scene.world, scene.fps, scene.substeps, scene.broadphase,
                                              rest_speed=scene.rest_speed),
    "ccd": lambda scene: CCDStepper(scene.world, scene.fps, scene.frames, rest_speed=scene.rest_speed, tc=scene.tc),
}


BLOCK_FRAMES = 64         # frames a stepper advances per call...
BLOCK_BYTES = 32 * 2**20  # ...unless that many frames of positions and velocities take more room than this


def simulate(scene: Scene, progress=None, max_events: int = MAX_EVENTS, storage: str = "float64"):
    """The state at every frame time, t = 0 included: a Trajectory with frames + 1 samples.

    A scene made of panels gives one Trajectory per panel (a list), one of chapters a list per
    chapter. `progress(frames)` is called as frames are done. The event log keeps the first
    `max_events` collisions (0 keeps none), so a long run of a busy scene stays bounded in
    memory; the per-frame collision counts are always complete, and a cut log is said once.

    `storage` (STORAGE) says how the frames are kept: "float64" as computed; "float32" half the
    memory (positions to about 1e-7 of their size); "positions" a quarter: positions and angles
    as float32, velocities and angular velocities not kept. The trajectory is allocated once,
    from its first block; the engine writes every later block's positions and velocities
    straight into it when it keeps them as computed (float64), and other blocks are copied in
    (peak memory: the trajectory plus one block of at most BLOCK_BYTES plus the engine's own
    arrays).
    """
    check_storage(storage)
    check_scene(scene, METHODS)
    return _simulate(scene, progress, max_events, storage)


def _simulate(scene: Scene, progress, max_events: int, storage: str):
    """simulate() of a scene already checked."""
    if scene.panels:
        return [_simulate(panel.scene, progress, max_events, storage) for panel in scene.panels]
    if scene.chapters:
        return [_simulate(chapter, progress, max_events, storage) for chapter in scene.chapters]
    recorder, kept, cut = Recorder(scene.frames + 1, storage, scene.world.n), 0, False
    with ctrl_c_safe():
        for block in stream(scene, progress=progress, into=recorder.views, checked=True):
            room = max(max_events - kept, 0)
            if len(block.events) > room:
                block.events, cut = block.events.take(slice(0, room)), True
            kept += len(block.events)
            recorder.add(block)
            del block  # the block's arrays go now, not when the next one has been made
    trajectory = recorder.trajectory()
    if cut and max_events > 0:
        warnings.warn(f"{scene.name}: only the first {max_events} collision events are kept in "
                      f"Trajectory.events; the per-frame collision counts are complete", stacklevel=3)
    if trajectory.approximate.any():
        warnings.warn(approximate_summary(trajectory.approximate.sum(), trajectory.frames, scene.name,
                                          trajectory.warnings), stacklevel=3)
    return trajectory


def block_frames(scene: Scene) -> int:
    """Frames per stepper call: BLOCK_FRAMES, fewer for the discrete method when that many
    frames of positions and velocities (32 bytes a body) would exceed BLOCK_BYTES (a million
    bodies: 1 frame). ccd keeps BLOCK_FRAMES."""
    if scene.method == "ccd":
        return BLOCK_FRAMES
    return int(max(1, min(BLOCK_FRAMES, BLOCK_BYTES // (32 * max(scene.world.n, 1)))))


def stream(scene: Scene, block: int | None = None, progress=None, stepper=None, into=None,
           checked: bool = False) -> Iterator[Trajectory]:
    """Yield the trajectory in consecutive blocks of at most `block` samples (by default
    block_frames), so that a long render holds only one block in memory. The first block
    starts with the t = 0 sample. Every block size gives the same bytes. `stepper`: one that
    METHODS built for this scene and that has not run yet (a benchmark reads its counters after).
    into(first, count): where the stepper is to write the positions and velocities of samples
    first .. first + count - 1 (Recorder.views), or None for new arrays; asked for every block,
    the first's row 0 receiving the state at t = 0. checked: the scene has passed check_scene
    already (the pipeline checks every panel's before it draws anything)."""
    if scene.world is None:
        raise ValueError(f"scene '{scene.name}' is made of panels or chapters; stream each one's scene")
    if not checked:
        check_scene(scene, METHODS)
    stepper = METHODS[scene.method](scene) if stepper is None else stepper
    world, total = scene.world, scene.frames
    block = block_frames(scene) if block is None else block
    first = 0
    while first <= total:
        count = min(block, total + 1 - first)
        if first == 0:  # the first block opens with the state at t = 0
            frames, events = _first_block(world, stepper, count, None if into is None else into(0, count))
        else:
            frames, events = stepper.run(count, into(first, count) if into is not None else None)
        require_finite(frames, first, scene)
        if progress is not None:
            progress(count - (first == 0))
        yield Trajectory(
            times=np.arange(first, first + count) / scene.fps, positions=frames.positions,
            velocities=frames.velocities, angles=frames.angles, angular_velocities=frames.angular_velocities,
            wall_collisions=frames.collisions[:, 0], pair_collisions=frames.collisions[:, 1],
            segment_collisions=frames.collisions[:, 2], candidates=frames.candidates,
            approximate=frames.approximate, hierarchy=frames.hierarchy, world=world, fps=scene.fps,
            events=events, method=scene.method, broadphase=stepper.broadphase, substeps=scene.substeps,
            profile=stepper.profile.seconds, warnings=stepper.warnings)
        first += count


def require_finite(frames: Frames, first: int, scene: Scene) -> None:
    """Refuse a block of frames (the first at sample `first`) in which a body's state is no
    longer a finite number, naming the first such frame: speeds, accelerations or sizes so
    large that the arithmetic overflows (a gravity of 1e300 made NaN within a frame). A state
    that is not finite stays so (NaN and inf survive every step, and such a body never sleeps),
    so the block's last frame tells, at the cost of n values rather than of the block."""
    state = [frames.positions, frames.velocities, frames.angles, frames.angular_velocities]
    if all(np.isfinite(array[-1]).all() for array in state if array.shape[0]):
        return
    finite = np.ones(len(frames.positions), np.bool_)
    for array in state:
        if array.shape[0]:
            finite &= np.isfinite(array.reshape(len(array), -1)).all(axis=1)
    frame = first + int(np.argmin(finite))
    raise ValueError(f"scene '{scene.name}': the {scene.method} method overflowed at frame {frame} "
                     f"(t = {frame / scene.fps:.4g} s): a body's position or velocity is no longer a finite "
                     f"number; the scene's speeds, accelerations or sizes are too large for double precision")


def _initial(world) -> Frames:
    return Frames(world.positions[None].copy(), world.velocities[None].copy(), world.angles[None].copy(),
                  world.angular_velocities[None].copy(), np.zeros((1, 3), np.int64), np.zeros(1, np.int64),
                  np.zeros(1, np.bool_), world_counts(world)[None])


def _first_block(world, stepper, count: int, into=None) -> tuple:
    """(Frames, Events) of the t = 0 sample followed by the first count - 1 frames. The stepper
    writes its positions and velocities straight after the initial state's row (no copy of the
    block's largest arrays), in `into` (positions, velocities) when given (Recorder.views: the
    trajectory's own rows), else in new arrays; the other arrays are joined, and those that
    repeat one row (constant_angles: bodies that never turn) stay a repeated row."""
    initial = _initial(world)
    if count == 1:
        return initial, Events.empty()
    positions, velocities = (np.empty((count, world.n, 2)), np.empty((count, world.n, 2))) if into is None else into
    positions[0], velocities[0] = initial.positions[0], initial.velocities[0]
    frames, events = stepper.run(count - 1, (positions[1:], velocities[1:]))
    joined = (_joined(a, b) for a, b in zip(initial[2:], frames[2:]))
    return Frames(positions, velocities, *joined), events


def _joined(initial: np.ndarray, frames: np.ndarray) -> np.ndarray:
    if _repeats_one_row(frames) and np.array_equal(initial[0], frames[0], equal_nan=True):
        return np.broadcast_to(frames[0], (len(frames) + 1,) + frames.shape[1:])
    return np.concatenate([initial, frames])


def _repeats_one_row(array: np.ndarray) -> bool:
    """Is array one row, or a read-only view repeating one row (stride 0 along frames)?"""
    return len(array) == 1 or (len(array) > 1 and array.strides[0] == 0)


_PER_FRAME = ("times", "positions", "velocities", "angles", "angular_velocities", "wall_collisions",
              "pair_collisions", "segment_collisions", "candidates", "approximate", "hierarchy")
_STATE = ("positions", "velocities", "angles", "angular_velocities")   # what storage= applies to
STORAGE = {"float64": (np.float64, _STATE), "float32": (np.float32, _STATE),
           "positions": (np.float32, ("positions", "angles"))}


def check_storage(storage) -> None:
    if storage not in STORAGE:
        raise ValueError(f"unknown storage {storage!r}; choose one of: {', '.join(STORAGE)}")


class Recorder:
    """A Trajectory of `samples` frames allocated once, filled block by block (add) as the
    stepper yields them: no list of blocks, no concatenation, so memory peaks at the
    trajectory plus one block. Arrays the blocks give as one repeated row (the angles of
    bodies that never turn) stay one repeated row; state fields `storage` does not keep are
    read-only NaN views (see Trajectory.storage)."""

    def __init__(self, samples: int, storage: str = "float64", bodies: int | None = None):
        check_storage(storage)
        self.samples, self.storage = samples, storage
        self.arrays, self.filled, self.events, self.head = {}, 0, [], None
        if bodies is not None and storage == "float64":   # the engine writes every block into these
            for name in ("positions", "velocities"):
                self.arrays[name] = np.empty((samples, bodies, 2))

    def add(self, block: Trajectory) -> None:
        dtype, kept = STORAGE[self.storage]
        start, end = self.filled, self.filled + len(block.times)
        for name in _PER_FRAME:
            value = getattr(block, name)
            if name in _STATE and name not in kept:
                value = np.broadcast_to(np.float32(np.nan), value.shape)
            self._write(name, value, start, end, dtype if name in _STATE else value.dtype)
        self.filled, self.head = end, block
        self.events.append(block.events)

    def views(self, start: int, count: int):
        """(positions, velocities) of samples start .. start + count - 1, for the engine to write
        its frames straight into (no second copy of the largest arrays), when the trajectory
        keeps both as computed: float64 storage, every row its own. Else None."""
        names = ("positions", "velocities")
        if self.storage != "float64" or any(self.arrays.get(name) is None for name in names):
            return None
        for name in names:   # a first block of one sample was kept as a repeated row: give it rows
            stored = self.arrays[name]
            if _repeats_one_row(stored):
                self.arrays[name] = np.empty(stored.shape, stored.dtype)
                self.arrays[name][:self.filled] = stored[:self.filled]
        return tuple(self.arrays[name][start:start + count] for name in names)

    def _write(self, name: str, value: np.ndarray, start: int, end: int, dtype) -> None:
        stored = self.arrays.get(name)
        if stored is not None and _written_in_place(stored[start:end], value):
            return   # the engine wrote these rows itself (views)
        row_shape = value.shape[1:]
        if stored is None and _repeats_one_row(value):
            self.arrays[name] = np.broadcast_to(value[0].astype(dtype), (self.samples,) + row_shape)
            return
        if stored is not None and _repeats_one_row(stored):
            if _repeats_one_row(value) and np.array_equal(stored[0], value[0].astype(dtype), equal_nan=True):
                return
            stored = self.arrays[name] = np.array(stored)  # a block that differs: keep every row after all
        if stored is None:
            stored = self.arrays[name] = np.empty((self.samples,) + row_shape, dtype)
        stored[start:end] = value

    def trajectory(self) -> Trajectory:
        if self.head is None or self.filled != self.samples:
            raise ValueError(f"the recorder holds {self.filled} of {self.samples} samples")
        head = self.head
        return Trajectory(**self.arrays, world=head.world, fps=head.fps, events=Events.concatenate(self.events),
                          method=head.method, broadphase=head.broadphase, substeps=head.substeps,
                          profile=dict(head.profile), warnings=list(head.warnings), storage=self.storage)


def _written_in_place(rows: np.ndarray, value: np.ndarray) -> bool:
    """Is value these very rows (the same memory, shape and layout)?"""
    return (rows.shape == value.shape and rows.dtype == value.dtype and rows.strides == value.strides
            and rows.__array_interface__["data"][0] == value.__array_interface__["data"][0])


def concatenate(blocks: list, storage: str = "float64") -> Trajectory:
    """Join consecutive blocks into one Trajectory."""
    recorder = Recorder(sum(len(block.times) for block in blocks), storage)
    for block in blocks:
        recorder.add(block)
    return recorder.trajectory()
