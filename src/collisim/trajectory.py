"""What a simulation returns: the state at every frame time, and its collision events."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

WALL, PAIR, SEGMENT = 0, 1, 2
EVENT_KINDS = ("wall", "pair", "segment")


@dataclass
class Events:
    """Collision events, one row each, sorted by time.

    time: (k,)      when the impact happened (discrete methods: the end of the step that found it)
    kind: (k,) int8 WALL, PAIR or SEGMENT
    i: (k,)         the particle
    j: (k,)         the other particle (PAIR, i < j), the wall 0..3 = left, right, bottom, top
                    (WALL), or the segment index (SEGMENT)
    impulse: (k,)   magnitude of the impulse on particle i along the contact normal
    point: (k, 2)   contact point
    """
    time: np.ndarray
    kind: np.ndarray
    i: np.ndarray
    j: np.ndarray
    impulse: np.ndarray
    point: np.ndarray

    @classmethod
    def empty(cls) -> "Events":
        return cls(np.zeros(0), np.zeros(0, np.int8), np.zeros(0, np.intp), np.zeros(0, np.intp),
                   np.zeros(0), np.zeros((0, 2)))

    @classmethod
    def concatenate(cls, parts: list) -> "Events":
        if not parts:
            return cls.empty()
        merged = cls(*(np.concatenate([getattr(p, name) for p in parts]) for name in
                       ("time", "kind", "i", "j", "impulse", "point")))
        order = np.lexsort((merged.j, merged.i, merged.kind, merged.time))
        return merged.take(order)

    def take(self, index) -> "Events":
        return Events(self.time[index], self.kind[index], self.i[index], self.j[index],
                      self.impulse[index], self.point[index])

    def __len__(self) -> int:
        return len(self.time)


@dataclass
class Trajectory:
    """The state at every frame time t = 0, 1/fps, ..., seconds (F = frames + 1 samples).

    times: (F,)
    positions: (F, n, 2)
    velocities: (F, n, 2)
    wall_hits, pair_hits, segment_hits: (F,)  collisions in the interval ending at each frame
    candidates: (F,)   broad-phase candidate pairs of the last step of each frame
    radii, masses: (n,)
    events: every collision, for pressure, flashes and measurements
    profile: seconds spent per phase (integrate, broad, narrow, response, walls, settle; step when
             fused; events for ccd)
    """
    times: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray
    radii: np.ndarray
    masses: np.ndarray
    wall_hits: np.ndarray
    pair_hits: np.ndarray
    segment_hits: np.ndarray
    candidates: np.ndarray
    events: Events = field(default_factory=Events.empty)
    method: str = "discrete"
    broadphase: str = ""
    substeps: int = 1
    profile: dict = field(default_factory=dict)
    warnings: list = field(default_factory=list)

    @property
    def frames(self) -> int:
        return len(self.times) - 1

    @property
    def collisions(self) -> np.ndarray:
        """Collisions of every kind per frame: (F,)."""
        return self.wall_hits + self.pair_hits + self.segment_hits

    def kinetic_energy(self) -> np.ndarray:
        """(F,) total kinetic energy at each frame."""
        return 0.5 * np.einsum("n,fnk,fnk->f", self.masses, self.velocities, self.velocities)

    def momentum(self) -> np.ndarray:
        """(F, 2) total momentum at each frame."""
        return np.einsum("n,fnk->fk", self.masses, self.velocities)

    def wall_pressure(self, box) -> float:
        """Mean pressure on the walls: total wall impulse / (time · perimeter)."""
        xmin, ymin, xmax, ymax = box
        perimeter = 2 * ((xmax - xmin) + (ymax - ymin))
        on_walls = self.events.kind == WALL
        return float(self.events.impulse[on_walls].sum() / (self.times[-1] * perimeter))
