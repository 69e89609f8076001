"""Discrete collision detection: step, then look for overlaps at the end of the step.

One step of dt reads as the pipeline (each block is timed into the profile):

    integrate     p += v·dt + ½·a·dt², v += a·dt
    broad phase   candidate pairs from the particles' bounding boxes
    narrow phase  keep the pairs that really touch
    response      elastic impulses, then overlap removal, in sorted pair order
    barriers      thin segments
    walls         the box
    settle        a wall bounce may push a particle back into its partner: separate this
                  step's contacts again and keep every circle in the box (positions only)

A frame is k substeps of dt/k. With one particle there are no pairs, and no pair phase runs.
With the grid broad phase and no profile wanted, the same kernels run fused in one compiled
call per block of frames (fused.py): identical bytes, without the per-phase Python calls.
"""
from __future__ import annotations

import numpy as np

from ..narrowphase.circles import touching_pairs
from ..response.elastic import resolve_contacts, separate_contacts
from ..trajectory import PAIR, SEGMENT, WALL, Events
from .block import FrameBlock
from .integrate import integrate
from .profile import Profile
from .walls import clamp_into_box, collide_walls


class DiscreteStepper:
    """Advances a copy of a world, a block of frames at a time."""

    def __init__(self, world, fps: float, substeps: int = 1, broadphase_method: str = "sweep_prune",
                 profile: Profile | None = None, fused: bool = True):
        self.world = world
        self.positions = world.positions.copy()
        self.velocities = world.velocities.copy()
        self.dt = 1.0 / fps / substeps
        self.substeps = int(substeps)
        self.profile = profile or Profile()
        self.step_count = 0
        self.warnings = []
        n = world.n
        self.broad = _broad_phase(broadphase_method) if n >= 2 else None
        self.broadphase = broadphase_method if n >= 2 else ""
        self._wall_buffers = (np.empty(4 * n, np.intp), np.empty(4 * n, np.intp),
                              np.empty(4 * n), np.empty((4 * n, 2)))
        self._segment_collider = _segment_collider(world)
        self._fused = None
        if fused and broadphase_method == "grid" and n >= 2 and self._segment_collider is None:
            from .fused import FusedGrid
            self._fused = FusedGrid(world, self.dt, self.substeps)

    def run(self, count: int) -> FrameBlock:
        """Advance `count` frames."""
        if self._fused is not None:
            self.profile.start()
            block = self._fused.run(self.positions, self.velocities, self.step_count, count)
            self.step_count += count * self.substeps
            self.profile.lap("step")
            return block
        n = self.world.n
        positions, velocities = np.empty((count, n, 2)), np.empty((count, n, 2))
        hits, candidates, events = np.zeros((count, 3), np.int64), np.zeros(count, np.int64), []
        for frame in range(count):
            for _ in range(self.substeps):
                candidates[frame] = self.step(hits[frame], events)
            positions[frame], velocities[frame] = self.positions, self.velocities
        return FrameBlock(positions, velocities, hits, candidates, Events.concatenate(events))

    def step(self, hits, events) -> int:
        """One step of dt: add its collisions to hits (wall, pair, segment) and its Events to
        events; return the number of broad-phase candidates."""
        w, profile = self.world, self.profile
        self.step_count += 1
        time = self.step_count * self.dt
        profile.start()
        integrate(self.positions, self.velocities, w.accelerations, self.dt)
        profile.lap("integrate")
        candidates, contacts = 0, None
        if self.broad is not None:
            candidates, contacts = self._collide_pairs(hits, events, time)
        if self._segment_collider is not None:
            hits[2] += self._segment_collider(self.positions, self.velocities, events, time)
            profile.lap("barriers")
        count, wall_hits = collide_walls(self.positions, self.velocities, w.accelerations, w.radii, w.masses, w.box,
                                         w.restitution, *self._wall_buffers)
        if count:
            particle, wall, impulse, point = (b[:count].copy() for b in self._wall_buffers)
            events.append(Events(np.full(count, time), np.full(count, WALL, np.int8), particle, wall, impulse, point))
        hits[0] += wall_hits
        profile.lap("walls")
        if contacts is not None and len(contacts):
            separate_contacts(self.positions, w.masses, w.radii, contacts)
            clamp_into_box(self.positions, w.radii, w.box)
            profile.lap("settle")
        return candidates

    def _collide_pairs(self, hits, events, time) -> int:
        w, profile = self.world, self.profile
        reach = w.radii[:, None]
        candidates = self.broad.pairs(self.positions - reach, self.positions + reach)
        profile.lap("broad")
        contacts = touching_pairs(self.positions, w.radii, candidates)
        profile.lap("narrow")
        impulse = np.empty(len(contacts))
        point = np.empty((len(contacts), 2))
        collisions = resolve_contacts(self.positions, self.velocities, w.masses, w.radii, contacts,
                                      w.restitution, impulse, point)
        if collisions:
            hit = impulse > 0
            events.append(Events(np.full(collisions, time), np.full(collisions, PAIR, np.int8),
                                 contacts[hit, 0].copy(), contacts[hit, 1].copy(), impulse[hit], point[hit]))
        hits[1] += collisions
        profile.lap("response")
        return len(candidates), contacts


def _broad_phase(method: str):
    """The broad phase object; imported only for scenes with pairs to find."""
    from .. import broadphase
    return broadphase.make(method)


def _segment_collider(world):
    """The thin-barrier phase, or None when the world has no barriers."""
    if len(world.segments) == 0:
        return None
    from ..narrowphase.segments import collide_segments

    def collide(positions, velocities, events, time) -> int:
        particle, segment, impulse, point = collide_segments(positions, velocities, world.radii, world.masses,
                                                             world.segments, world.restitution)
        if len(particle):
            events.append(Events(np.full(len(particle), time), np.full(len(particle), SEGMENT, np.int8),
                                 particle, segment, impulse, point))
        return len(particle)
    return collide
