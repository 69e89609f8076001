"""Run a scene: stream the trajectory in blocks of frames, or collect it whole."""
from __future__ import annotations

from typing import Iterator

import numpy as np

from ..scene import Scene
from ..trajectory import Events, Trajectory
from .block import FrameBlock
from .discrete import DiscreteStepper
from .profile import Profile


def simulate(scene: Scene, progress=None):
    """The state at every frame time, t = 0 included: a Trajectory with frames + 1 samples.

    A scene made of panels gives one Trajectory per panel (a list), one of chapters a list per
    chapter. `progress(frames)` is called as frames are done.
    """
    if scene.panels:
        return [simulate(panel.scene, progress) for panel in scene.panels]
    if scene.chapters:
        return [simulate(chapter, progress) for chapter in scene.chapters]
    return concatenate(list(stream(scene, progress=progress)))


def stream(scene: Scene, block: int = 64, progress=None, phases: bool = False) -> Iterator[Trajectory]:
    """Yield the trajectory in consecutive blocks of at most `block` samples, so that a long
    render holds only one block in memory. The first block starts with the t = 0 sample.
    `phases` times every phase of the discrete step separately (slower: no fused step)."""
    if scene.world is None:
        raise ValueError(f"scene '{scene.name}' is made of panels or chapters; stream each one's scene")
    if scene.method == "ccd":
        from .continuous import CCDStepper
        stepper = CCDStepper(scene.world, scene.fps, profile=Profile())
    else:
        stepper = DiscreteStepper(scene.world, scene.fps, scene.substeps, scene.broadphase, fused=not phases)
    yield from _blocks(scene, stepper, block, progress)


def _blocks(scene: Scene, stepper, block: int, progress) -> Iterator[Trajectory]:
    world, total = scene.world, scene.frames
    first = 0
    while first <= total:
        count = min(block, total + 1 - first)
        if first == 0:  # the first block opens with the state at t = 0
            initial = FrameBlock(world.positions[None].copy(), world.velocities[None].copy(),
                                 np.zeros((1, 3), np.int64), np.zeros(1, np.int64), Events.empty())
            frames = _join(initial, stepper.run(count - 1)) if count > 1 else initial
        else:
            frames = stepper.run(count)
        if progress is not None:
            progress(count - (first == 0))
        yield Trajectory(
            times=np.arange(first, first + count) / scene.fps, positions=frames.positions,
            velocities=frames.velocities, radii=world.radii, masses=world.masses, wall_hits=frames.hits[:, 0],
            pair_hits=frames.hits[:, 1], segment_hits=frames.hits[:, 2], candidates=frames.candidates,
            events=frames.events, method=scene.method, broadphase=stepper.broadphase, substeps=scene.substeps,
            profile=stepper.profile.seconds, warnings=stepper.warnings)
        first += count


def _join(a: FrameBlock, b: FrameBlock) -> FrameBlock:
    return FrameBlock(*(np.concatenate([x, y]) for x, y in zip(a[:4], b[:4])), Events.concatenate([a.events, b.events]))


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
