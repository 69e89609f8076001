"""The `ccd` method as the engine runs it: a block of frames at a time.

The compiled event loop (events.py) runs each block from the exact state at the block's
start, like the discrete stepper, so the rest of the pipeline does not care which method
produced the frames.
"""
from __future__ import annotations

import time
import warnings

import numpy as np

from ...model.trajectory import Events
from ..discrete import new_frames
from ..profile import Profile
from .events import simulate_events


class CCDStepper:
    """Advances a copy of a world with continuous collision detection."""

    broadphase = ""   # the event loop finds its own candidates

    def __init__(self, world, fps: float, profile: Profile | None = None, max_events_per_frame: int = 100_000):
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

    def run(self, count: int):
        """Advance `count` frames: (Frames, Events)."""
        w = self.world
        gravity = w.accelerations[0] if w.n else w.gravity
        start = time.perf_counter()
        result = simulate_events(self.positions, self.velocities, gravity, w.radii, w.masses, w.box,
                                 w.restitution, w.segments, self.frame_dt, count, self.max_events)
        self.profile.add("events", time.perf_counter() - start)
        if result.budget_exceeded.any():
            self._warn(self._frames_done + int(np.argmax(result.budget_exceeded)))
        offset = self._frames_done * self.frame_dt
        self.positions, self.velocities = result.positions[-1].copy(), result.velocities[-1].copy()
        out = new_frames(count, w.n)
        out.positions[:], out.velocities[:] = result.positions[1:], result.velocities[1:]
        # circles turn freely between contacts, and ccd's contacts have no torque
        elapsed = (self._frames_done + np.arange(1, count + 1)) * self.frame_dt
        out.angles[:] = w.angles + np.outer(elapsed, w.angular_velocities)
        out.angular_velocities[:] = w.angular_velocities
        out.collisions[:] = np.column_stack([result.wall_collisions, result.pair_collisions,
                                             result.segment_collisions])[1:]
        self._frames_done += count
        events = Events(result.time + offset, result.kind, result.i, result.j, result.impulse, result.point)
        return out, events

    def _warn(self, frame: int) -> None:
        message = (f"ccd: more than {self.max_events} events in frame {frame} (resting contact or "
                   f"inelastic collapse); the frame was finished without exact events")
        self.warnings.append(message)
        warnings.warn(message, stacklevel=3)
