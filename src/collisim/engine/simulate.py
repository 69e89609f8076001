"""Run a scene: stream the trajectory in blocks of frames, or collect it whole."""
from __future__ import annotations

import warnings
from typing import Iterator

import numpy as np

from ..model.scene import Scene
from ..model.trajectory import Events, Trajectory, approximate_summary
from .ccd.stepper import CCDStepper
from .discrete import DiscreteStepper, Frames

# The methods, by the name a scene gives: each builds a stepper with run(count) -> (Frames, Events).
METHODS = {
    "discrete": lambda scene: DiscreteStepper(scene.world, scene.fps, scene.substeps, scene.broadphase),
    "ccd": lambda scene: CCDStepper(scene.world, scene.fps, scene.frames, rest_speed=scene.rest_speed, tc=scene.tc),
}


MAX_EVENTS = 10_000_000   # about 500 MB of event log; the per-frame counts are always complete


def simulate(scene: Scene, progress=None, max_events: int = MAX_EVENTS):
    """The state at every frame time, t = 0 included: a Trajectory with frames + 1 samples.

    A scene made of panels gives one Trajectory per panel (a list), one of chapters a list per
    chapter. `progress(frames)` is called as frames are done. The event log keeps the first
    `max_events` collisions (0 keeps none), so a long run of a busy scene stays bounded in
    memory; the per-frame collision counts are always complete, and a cut log is said once.
    """
    if scene.panels:
        return [simulate(panel.scene, progress, max_events) for panel in scene.panels]
    if scene.chapters:
        return [simulate(chapter, progress, max_events) for chapter in scene.chapters]
    blocks, kept, cut = [], 0, False
    for block in stream(scene, progress=progress):
        room = max(max_events - kept, 0)
        if len(block.events) > room:
            block.events, cut = block.events.take(slice(0, room)), True
        kept += len(block.events)
        blocks.append(block)
    trajectory = concatenate(blocks)
    if cut and max_events > 0:
        warnings.warn(f"{scene.name}: only the first {max_events} collision events are kept in "
                      f"Trajectory.events; the per-frame collision counts are complete", stacklevel=2)
    if trajectory.approximate.any():
        warnings.warn(approximate_summary(trajectory.approximate.sum(), trajectory.frames, scene.name,
                                          trajectory.warnings), stacklevel=2)
    return trajectory


def stream(scene: Scene, block: int = 64, progress=None) -> Iterator[Trajectory]:
    """Yield the trajectory in consecutive blocks of at most `block` samples, so that a long
    render holds only one block in memory. The first block starts with the t = 0 sample."""
    if scene.world is None:
        raise ValueError(f"scene '{scene.name}' is made of panels or chapters; stream each one's scene")
    stepper = METHODS[scene.method](scene)
    world, total = scene.world, scene.frames
    first = 0
    while first <= total:
        count = min(block, total + 1 - first)
        if first == 0:  # the first block opens with the state at t = 0
            frames, events = _join(_initial(world), *stepper.run(count - 1)) if count > 1 else (_initial(world),
                                                                                                Events.empty())
        else:
            frames, events = stepper.run(count)
        if progress is not None:
            progress(count - (first == 0))
        yield Trajectory(
            times=np.arange(first, first + count) / scene.fps, positions=frames.positions,
            velocities=frames.velocities, angles=frames.angles, angular_velocities=frames.angular_velocities,
            wall_collisions=frames.collisions[:, 0], pair_collisions=frames.collisions[:, 1],
            segment_collisions=frames.collisions[:, 2], candidates=frames.candidates,
            approximate=frames.approximate, world=world, fps=scene.fps,
            events=events, method=scene.method, broadphase=stepper.broadphase, substeps=scene.substeps,
            profile=stepper.profile.seconds, warnings=stepper.warnings)
        first += count


def _initial(world) -> Frames:
    return Frames(world.positions[None].copy(), world.velocities[None].copy(), world.angles[None].copy(),
                  world.angular_velocities[None].copy(), np.zeros((1, 3), np.int64), np.zeros(1, np.int64),
                  np.zeros(1, np.bool_))


def _join(initial: Frames, frames: Frames, events: Events) -> tuple:
    return Frames(*(np.concatenate([a, b]) for a, b in zip(initial, frames))), events


_PER_FRAME = ("times", "positions", "velocities", "angles", "angular_velocities", "wall_collisions",
              "pair_collisions", "segment_collisions", "candidates", "approximate")


def concatenate(blocks: list) -> Trajectory:
    """Join consecutive blocks into one Trajectory."""
    head = blocks[-1]
    joined = {name: np.concatenate([getattr(b, name) for b in blocks]) for name in _PER_FRAME}
    return Trajectory(**joined, world=head.world, fps=head.fps, events=Events.concatenate([b.events for b in blocks]),
                      method=head.method, broadphase=head.broadphase, substeps=head.substeps,
                      profile=dict(head.profile), warnings=list(head.warnings))
