"""The `ccd` method: exact event-driven motion, sampled at frame times.

The compiled event loop (collisim.ccd.events) runs a block of frames at a time from the exact
state at the block's start; this stepper hands its samples out one frame at a time, like the
discrete stepper, so the rest of the pipeline does not care which method produced them.
"""
from __future__ import annotations

import warnings

import numpy as np

from ..trajectory import Events
from .profile import Profile

BLOCK_FRAMES = 64


class CCDStepper:
    """Advances a copy of a world frame by frame with continuous collision detection."""

    broad = None           # the event loop finds its own candidates
    last_candidates = 0

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
        self._block = None
        self._row = 0

    def frame(self):
        """Advance one frame; return (wall hits, pair hits, segment hits, list of Events)."""
        if self._block is None or self._row >= len(self._block.positions) - 1:
            self._run_block()
        self._row += 1
        b, row = self._block, self._row
        self.positions = b.positions[row]
        self.velocities = b.velocities[row]
        self._frames_done += 1
        mine = b.event_frame == row
        events = Events(b.time[mine], b.kind[mine], b.i[mine], b.j[mine], b.impulse[mine], b.point[mine])
        hits = np.array([b.wall_counts[row], b.pair_counts[row], b.segment_counts[row]], np.int64)
        return hits, [events] if len(events) else []

    def _run_block(self) -> None:
        from ..ccd import simulate_events
        w = self.world
        self.profile.start()
        offset = self._frames_done * self.frame_dt
        result = simulate_events(self.positions, self.velocities, w.accelerations[0] if w.n else w.gravity,
                                 w.radii, w.masses, w.box, w.restitution, w.segments, self.frame_dt,
                                 BLOCK_FRAMES, self.max_events)
        self.profile.lap("events")
        self._block = _Block(result, offset, self.frame_dt)
        self._row = 0
        if result.budget_exceeded.any():
            first = self._frames_done + int(np.argmax(result.budget_exceeded))
            message = (f"ccd: more than {self.max_events} events in frame {first} (resting contact or "
                       f"inelastic collapse); the frame was finished without exact events")
            self.warnings.append(message)
            warnings.warn(message, stacklevel=2)


class _Block:
    """One run of the event loop, with event times shifted to scene time."""

    def __init__(self, result, offset: float, frame_dt: float):
        self.positions, self.velocities = result.positions, result.velocities
        frame_ends = np.arange(1, len(result.positions)) * frame_dt
        # an event at t belongs to the frame whose interval (t_{f-1}, t_f] holds it
        self.event_frame = np.searchsorted(frame_ends, result.time, side="left") + 1
        self.time = result.time + offset
        self.kind, self.i, self.j = result.kind, result.i, result.j
        self.impulse, self.point = result.impulse, result.point
        self.wall_counts, self.pair_counts = result.wall_counts, result.pair_counts
        self.segment_counts = result.segment_counts
