"""The `ccd` method: exact event-driven motion, sampled at frame times.

The compiled event loop (collisim.ccd.events) runs a block of frames at a time from the exact
state at the block's start, like the discrete stepper, so the rest of the pipeline does not
care which method produced the frames.
"""
from __future__ import annotations

import warnings

import numpy as np

from ..trajectory import Events
from .block import FrameBlock
from .profile import Profile


class CCDStepper:
    """Advances a copy of a world with continuous collision detection."""

    broadphase = ""   # the event loop finds its own candidates

    def __init__(self, world, fps: float, profile: Profile | None = None,
                 max_events_per_frame: int = 100_000):
        if not world.uniform_acceleration:
            raise ValueError("method ccd needs one uniform gravity for all particles")
        self.world = world
        self.frame_dt = 1.0 / fps
        self.max_events = max_events_per_frame
        self.positions = world.positions.copy()
        self.velocities = world.velocities.copy()
        self.profile = profile or Profile()
        self.warnings = []
        self._frames_done = 0

    def run(self, count: int) -> FrameBlock:
        """Advance `count` frames."""
        from ..ccd import simulate_events
        w = self.world
        self.profile.start()
        gravity = w.accelerations[0] if w.n else w.gravity
        result = simulate_events(self.positions, self.velocities, gravity, w.radii, w.masses, w.box,
                                 w.restitution, w.segments, self.frame_dt, count, self.max_events)
        self.profile.lap("events")
        if result.budget_exceeded.any():
            self._warn(self._frames_done + int(np.argmax(result.budget_exceeded)))
        offset = self._frames_done * self.frame_dt
        self._frames_done += count
        self.positions, self.velocities = result.positions[-1].copy(), result.velocities[-1].copy()
        hits = np.column_stack([result.wall_counts, result.pair_counts, result.segment_counts])[1:]
        events = Events(result.time + offset, result.kind, result.i, result.j, result.impulse, result.point)
        return FrameBlock(result.positions[1:], result.velocities[1:], hits, np.zeros(count, np.int64), events)

    def _warn(self, frame: int) -> None:
        message = (f"ccd: more than {self.max_events} events in frame {frame} (resting contact or "
                   f"inelastic collapse); the frame was finished without exact events")
        self.warnings.append(message)
        warnings.warn(message, stacklevel=3)
