"""Discrete collision detection: step, then look for overlaps at the end of the step.

One step of dt reads as the pipeline (each block is timed into the profile):

    integrate     p += v·dt + ½·a·dt², v += a·dt
    broad phase   candidate pairs from the particles' bounding boxes
    narrow phase  keep the pairs that really touch
    response      elastic impulses, then overlap removal, in sorted pair order
    barriers      thin segments
    walls         the box

A frame is k substeps of dt/k. With one particle there are no pairs, and no pair phase runs.
"""
from __future__ import annotations

import numpy as np

from ..narrowphase.circles import touching_pairs
from ..response.elastic import resolve_contacts
from ..trajectory import PAIR, SEGMENT, WALL, Events
from .integrate import integrate
from .profile import Profile
from .walls import collide_walls


class DiscreteStepper:
    """Advances a copy of a world frame by frame."""

    def __init__(self, world, fps: float, substeps: int = 1, broadphase_method: str = "sweep_prune",
                 profile: Profile | None = None):
        self.world = world
        self.positions = world.positions.copy()
        self.velocities = world.velocities.copy()
        self.dt = 1.0 / fps / substeps
        self.substeps = int(substeps)
        self.profile = profile or Profile()
        self.time = 0.0
        self.step_count = 0
        n = world.n
        self.broad = _broad_phase(broadphase_method) if n >= 2 else None
        self.last_candidates = 0
        self.warnings = []
        self._wall_buffers = (np.empty(4 * n, np.intp), np.empty(4 * n, np.intp),
                              np.empty(4 * n), np.empty((4 * n, 2)))
        self._segment_stepper = _segment_collider(world)

    def frame(self):
        """Advance one frame; return (wall hits, pair hits, segment hits, list of Events)."""
        hits = np.zeros(3, np.int64)
        events = []
        for _ in range(self.substeps):
            self.step_count += 1
            self.time = self.step_count * self.dt
            self.step(hits, events)
        return hits, events

    def step(self, hits, events) -> None:
        w, profile = self.world, self.profile
        profile.start()
        integrate(self.positions, self.velocities, w.accelerations, self.dt)
        profile.lap("integrate")
        if self.broad is not None:
            hits[1] += self._collide_pairs(events)
        if self._segment_stepper is not None:
            hits[2] += self._segment_stepper(self, events)
            profile.lap("barriers")
        count, wall_hits = collide_walls(self.positions, self.velocities, w.accelerations, w.radii, w.masses, w.box,
                                         w.restitution, *self._wall_buffers)
        if count:
            particle, wall, impulse, point = (b[:count].copy() for b in self._wall_buffers)
            events.append(Events(np.full(count, self.time), np.full(count, WALL, np.int8),
                                 particle, wall, impulse, point))
        hits[0] += wall_hits
        profile.lap("walls")

    def _collide_pairs(self, events) -> int:
        w, profile = self.world, self.profile
        reach = w.radii[:, None]
        candidates = self.broad.pairs(self.positions - reach, self.positions + reach)
        self.last_candidates = len(candidates)
        profile.lap("broad")
        contacts = touching_pairs(self.positions, w.radii, candidates)
        profile.lap("narrow")
        if len(contacts) == 0:
            profile.lap("response")
            return 0
        impulse = np.empty(len(contacts))
        point = np.empty((len(contacts), 2))
        collisions = resolve_contacts(self.positions, self.velocities, w.masses, w.radii, contacts,
                                      w.restitution, impulse, point)
        hit = impulse > 0
        if collisions:
            events.append(Events(np.full(collisions, self.time), np.full(collisions, PAIR, np.int8),
                                 contacts[hit, 0].copy(), contacts[hit, 1].copy(), impulse[hit], point[hit]))
        profile.lap("response")
        return collisions


def _broad_phase(method: str):
    """The broad phase object; imported only for scenes with pairs to find."""
    from .. import broadphase
    return broadphase.make(method)


def _segment_collider(world):
    """The thin-barrier phase, or None when the world has no barriers."""
    if len(world.segments) == 0:
        return None
    from ..narrowphase.segments import collide_segments_events

    def collide(stepper, events) -> int:
        found = collide_segments_events(stepper.positions, stepper.velocities, world.radii, world.masses,
                                        world.segments, world.restitution)
        if found is None:
            return 0
        particle, segment, impulse, point = found
        events.append(Events(np.full(len(particle), stepper.time), np.full(len(particle), SEGMENT, np.int8),
                             particle, segment, impulse, point))
        return len(particle)
    return collide
