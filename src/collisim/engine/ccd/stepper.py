"""The `ccd` method as the engine runs it: a block of frames at a time, one event loop.

The event loop (events.py) keeps its state — bodies at their own reference times, the event
queue, the cell grid — from one block to the next, and frame f is always sampled at
t = f / fps, so streaming in blocks of any size gives the same bytes as one block. The rest of
the pipeline does not care which method produced the frames.
"""
from __future__ import annotations

import time

import numpy as np

from ...core.kinds import MAP, SEGMENT
from ...model.trajectory import Events
from ..frames import constant_angles, new_frames
from ..profile import Profile
from ..start import check_ccd_covers
from .eventqueue import CELL
from .events import run, sorted_log, start_event_loop
from .fallback import FALLBACK_NOTE


def map_events(events: Events, own_segments: int) -> Events:
    """Label collisions with the map's chains as kinds.MAP, numbered within the map."""
    on_map = (events.kind == SEGMENT) & (events.j >= own_segments)
    if on_map.any():
        events.kind[on_map] = MAP
        events.j[on_map] -= own_segments
        events = Events.concatenate([events])   # back to canonical (time, kind, i, j) order
    return events


class CCDStepper:
    """Advances a copy of a world with continuous collision detection, for `frames` frames."""

    broadphase = ""   # the event loop finds its own candidates

    def __init__(self, world, fps: float, frames: int, profile: Profile | None = None,
                 max_events_per_frame: int | None = None, rest_speed: float | None = None, tc: float | None = None):
        check_ccd_covers(world)
        self.world = world
        self.frame_dt = 1.0 / fps
        # the budget grows with n: a gas of 20 000 fast disks needs more events a frame than 200
        self.max_events = max(100_000, 64 * world.n) if max_events_per_frame is None else max_events_per_frame
        gravity = world.accelerations[0] if world.n else world.gravity
        self.loop = start_event_loop(world.positions, world.velocities, gravity, world.radii, world.masses,
                                     world.box, world.restitution, world.level_segments, frames * self.frame_dt,
                                     rest_speed=rest_speed, tc=tc)
        self.profile = profile or Profile()
        self.warnings = []
        self._frames_done = 0

    def run(self, count: int, into=None):
        """Advance `count` frames: (Frames, Events). into: where to write the frames' positions
        and velocities (frames.new_frames), or None for new arrays."""
        w = self.world
        turning = bool(np.any(w.angular_velocities != 0.0))
        out = new_frames(count, w.n, turning, into)
        over_budget = np.zeros(count, np.bool_)
        start = time.perf_counter()
        log, queue = run(self.loop, self.frame_dt, self._frames_done + 1, count, self.max_events, out.positions,
                         out.velocities, out.collisions, over_budget)
        self.loop = self.loop._replace(queue=queue)
        self.profile.add("events", time.perf_counter() - start)
        out.approximate[:] = over_budget
        if over_budget.any() and not self.warnings:
            self.warnings.append(f"more than {self.max_events} events in a frame, first at frame "
                                 f"{self._frames_done + 1 + int(np.argmax(over_budget))}; {FALLBACK_NOTE}")
        # circles turn freely between contacts, and ccd's contacts have no torque
        if turning:
            elapsed = (self._frames_done + np.arange(1, count + 1)) * self.frame_dt
            out.angles[:] = w.angles + np.outer(elapsed, w.angular_velocities)
            out.angular_velocities[:] = w.angular_velocities
        else:
            out = constant_angles(out, w.angles.copy(), w.angular_velocities.copy())
        self._frames_done += count
        return out, map_events(Events(*sorted_log(log)), len(w.segments))

    def events_processed(self) -> dict:
        """Events processed so far, by kind: "collisions" (contacts with walls, particles and
        segments, impulse or not) and "bookkeeping" (cell crossings and slides off a segment's
        end: no velocity changes, but each is predicted again like a collision)."""
        tally = self.loop.tally
        return {"collisions": int(tally[:CELL].sum()), "bookkeeping": int(tally[CELL:].sum())}
