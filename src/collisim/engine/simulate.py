"""Run a scene: stream the trajectory in blocks of frames, or collect it whole."""
from __future__ import annotations

from typing import Iterator

import numpy as np

from ..scene import Scene
from ..trajectory import Events, Trajectory
from .discrete import DiscreteStepper
from .profile import Profile


def simulate(scene: Scene, progress=None):
    """The state at every frame time, t = 0 included: a Trajectory with frames + 1 samples.

    A scene made of panels gives one Trajectory per panel (a list). `progress(frames)` is
    called as frames are done.
    """
    if scene.panels:
        return [simulate(panel.scene, progress) for panel in scene.panels]
    return concatenate(list(stream(scene, progress=progress)))


def stream(scene: Scene, block: int = 64, progress=None) -> Iterator[Trajectory]:
    """Yield the trajectory in consecutive blocks of at most `block` samples, so that a long
    render holds only one block in memory. The first block starts with the t = 0 sample."""
    if scene.world is None:
        raise ValueError(f"scene '{scene.name}' is made of panels; stream each panel's scene")
    if scene.method == "ccd":
        from .continuous import CCDStepper
        stepper = CCDStepper(scene.world, scene.fps, profile=Profile())
    else:
        stepper = DiscreteStepper(scene.world, scene.fps, scene.substeps, scene.broadphase)
    yield from _blocks(scene, stepper, block, progress)


def _blocks(scene: Scene, stepper, block: int, progress) -> Iterator[Trajectory]:
    world, total = scene.world, scene.frames
    first = 0
    while first <= total:
        last = min(first + block, total + 1)
        count = last - first
        positions = np.empty((count, world.n, 2))
        velocities = np.empty((count, world.n, 2))
        hits = np.zeros((count, 3), np.int64)
        candidates = np.zeros(count, np.int64)
        events = []
        for row, frame in enumerate(range(first, last)):
            if frame > 0:
                hits[row], frame_events = stepper.frame()
                events.extend(frame_events)
                candidates[row] = stepper.last_candidates
            positions[row] = stepper.positions
            velocities[row] = stepper.velocities
        if progress is not None:
            progress(count - (first == 0))
        yield Trajectory(
            times=np.arange(first, last) / scene.fps, positions=positions, velocities=velocities,
            radii=world.radii, masses=world.masses, wall_hits=hits[:, 0], pair_hits=hits[:, 1],
            segment_hits=hits[:, 2], candidates=candidates, events=Events.concatenate(events),
            method=scene.method, broadphase=scene.broadphase if stepper.broad is not None else "",
            substeps=scene.substeps, profile=stepper.profile.seconds, warnings=stepper.warnings)
        first = last


def concatenate(blocks: list) -> Trajectory:
    """Join consecutive blocks into one Trajectory."""
    head = blocks[-1]
    stack = lambda name: np.concatenate([getattr(b, name) for b in blocks])  # noqa: E731
    return Trajectory(
        times=stack("times"), positions=stack("positions"), velocities=stack("velocities"),
        radii=head.radii, masses=head.masses, wall_hits=stack("wall_hits"), pair_hits=stack("pair_hits"),
        segment_hits=stack("segment_hits"), candidates=stack("candidates"),
        events=Events.concatenate([b.events for b in blocks]), method=head.method,
        broadphase=head.broadphase, substeps=head.substeps, profile=dict(head.profile),
        warnings=list(head.warnings))
