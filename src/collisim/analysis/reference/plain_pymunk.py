"""pymunk as a user would run it: the speed baseline of collisim's benchmarks.

`pymunk_mirror` sets Chipmunk up to match collisim's physics as closely as it can and records
every contact through Python callbacks (begin and post_solve), with a tiny slop, almost no
overlap bias and 30 solver iterations. That is the right tool to check physics, and the wrong
one to time: in `collisim bench accuracy` its steps cost 1.9–7.6 × plain pymunk's at one
substep (measured). This module builds the Space a user would write for the same World, and
times `space.step` and nothing else.

What it sets up
---------------
* one dynamic `pymunk.Body(mass, moment)` per body with the World's mass and moment of
  inertia (`World.inertias`: ½·m·r² for a disc, the polygon's own for a polygon), angle and
  spin, and a `pymunk.Circle` or a `pymunk.Poly` of the same vertices on it (reference/bodies.py);
* materials matched to the World's: Chipmunk's default collision handler multiplies the two
  shapes' elasticities and frictions, so every shape, walls and segments included, gets √e and
  √μ, and every pair and every body on a wall meets with exactly the World's e and μ (shapes
  set to e and μ would meet each other with e² and μ²: a softer, more slippery pile than the
  World's; the elastic frictionless gases are the same either way);
* the box as four static segments of radius 0 lying on its edges, each on its own static body
  (a static body costs nothing in a step; it only lets a recorded run tell the walls apart),
  and the World's thin segments (a map's exact outline included) as static segments of radius
  0, each on its own static body as well;
* space.gravity = the World's gravity (per-particle accelerations need a velocity function per
  body, a Python call per body per step: pymunk offers nothing cheaper);
* everything else left at Chipmunk's defaults: no collision handler, collision_slop 0.1,
  collision_bias (10 % of an overlap corrected per 1/60 s), 10 iterations, damping 1,
  collision_persistence 3, the default spatial index, no sleeping (`sleep_time_threshold`
  turns Chipmunk's sleeping on: a body idle that long sleeps, with its island).

A frame of k substeps is k calls of `space.step(1 / (fps·k))`. `time_steps` times exactly those
calls. A recorded run (`record`) also reads, after each step, every body's pose and velocity
and every touching arbiter through pymunk's batch API (no callbacks in the Space), which costs
Python time a user who only steps would not pay: recorded runs are for accuracy, never timed.

From the arbiters a recorded run gets what the mirror's callbacks give: a contact counts once
when it begins (`is_first_contact`, as Chipmunk's begin callback), and each step with a non-zero
impulse is an event with the arbiter's total impulse, at the midpoint of the first contact's two
surface points.

Thin walls are what a user writes, and they are why a fast gas needs substeps here: a circle
whose centre passes a wall's line within one step is pushed out of the box (a radius-0 segment
is two-sided), and then flies away. `pymunk_mirror` uses thick walls so that its comparisons are
about pair physics; the baseline keeps what a user would get.
"""
from __future__ import annotations

import math
import time

import numpy as np
import pymunk
import pymunk.batch

from ...core.kinds import PAIR, SEGMENT, WALL
from ...model.trajectory import Events, Trajectory
from .bodies import add_body, events_from_rows, read_state

_A = pymunk.batch.ArbiterFields
_ARBITER_FIELDS = (_A.BODY_A_ID | _A.BODY_B_ID | _A.IS_FIRST_CONTACT | _A.CONTACT_COUNT | _A.TOTAL_IMPULSE
                   | _A.POINT_A_1 | _A.POINT_B_1)


class PlainPymunk:
    """A default pymunk Space holding a World (see the module docstring)."""

    def __init__(self, world, sleep_time_threshold: float | None = None):
        self.world = world
        self.space = pymunk.Space()
        if sleep_time_threshold is not None:
            self.space.sleep_time_threshold = float(sleep_time_threshold)
        self.space.damping = float(world.damping)
        uniform = world.uniform_acceleration
        if uniform:
            self.space.gravity = tuple(float(a) for a in (world.accelerations[0] if world.n else world.gravity))
        self.bodies = []
        for i, moment in enumerate(world.inertias):   # each read once: both look at every body
            body, shape = add_body(self.space, world, i, moment, uniform)
            self._set_material(shape)
            self.bodies.append(body)
        xmin, ymin, xmax, ymax = (float(v) for v in world.box)
        # collisim's wall order: left, right, bottom, top
        edges = [(xmin, ymin, xmin, ymax), (xmax, ymin, xmax, ymax), (xmin, ymin, xmax, ymin), (xmin, ymax, xmax, ymax)]
        self.walls = [self._static_segment(edge) for edge in edges]
        self.segments = [self._static_segment(segment) for segment in world.level_segments]
        self._buffer = pymunk.batch.Buffer()

    def _set_material(self, shape) -> None:
        """Every shape, walls and segments included: √e and √μ, so that pairs meet with e and μ
        (see the module docstring)."""
        shape.elasticity = math.sqrt(float(self.world.restitution))
        shape.friction = math.sqrt(float(self.world.friction))

    def _static_segment(self, ends) -> pymunk.Body:
        x0, y0, x1, y1 = (float(v) for v in ends)
        body = pymunk.Body(body_type=pymunk.Body.STATIC)
        shape = pymunk.Segment(body, (x0, y0), (x1, y1), 0.0)
        self._set_material(shape)
        self.space.add(body, shape)
        return body

    def abandon(self) -> None:
        """Let this space go without freeing it: its memory stays with the process until it
        exits. Chipmunk frees a space body by body, and each removal searches the space's array
        of bodies and passes over every cached contact, so freeing a space is quadratic in its
        size: about a second at 40 000 bodies, several minutes at 1 000 000.
        For benchmarks of large worlds only."""
        from pymunk._chipmunk_cffi import ffi

        ffi.gc(self.space._space, None)      # detach each destructor: nothing is freed
        for shape in self.space.shapes:
            ffi.gc(shape._shape, None)
        for body in {id(body): body for body in [*self.space.bodies, *(s.body for s in self.space.shapes)]}.values():
            ffi.gc(body._body, None)

    # --- stepping ------------------------------------------------------------------------------

    def time_steps(self, fps: float, frames: int, substeps: int = 1) -> float:
        """Advance `frames` frames of `substeps` calls of space.step each: wall seconds spent in
        those calls (nothing is read or recorded)."""
        step, dt = self.space.step, 1.0 / fps / substeps
        start = time.perf_counter()
        for _ in range(frames * substeps):
            step(dt)
        return time.perf_counter() - start

    def state(self) -> tuple:
        """(positions (n, 2), velocities (n, 2), angles (n,), angular velocities (n,)) in the
        World's order, read in one batch call (body by body once sleeping is on: Chipmunk keeps
        sleeping bodies out of the space's body array, which the batch call reads)."""
        if self.space.sleep_time_threshold == math.inf:
            return read_state(self.space, self.world.n, self._buffer)
        bodies = self.bodies
        return (np.array([tuple(b.position) for b in bodies]).reshape(-1, 2),
                np.array([tuple(b.velocity) for b in bodies]).reshape(-1, 2),
                np.array([b.angle for b in bodies]), np.array([b.angular_velocity for b in bodies]))

    def record(self, fps: float, frames: int, substeps: int = 1) -> Trajectory:
        """Advance `frames` frames and record every frame and every contact (see the module
        docstring); profile["step"] is the time spent in space.step alone."""
        n, dt = self.world.n, 1.0 / fps / substeps
        positions, velocities = np.empty((frames + 1, n, 2)), np.empty((frames + 1, n, 2))
        angles, spins = np.empty((frames + 1, n)), np.empty((frames + 1, n))
        counts = np.zeros((frames + 1, 3), np.int64)
        positions[0], velocities[0], angles[0], spins[0] = self.state()
        reader = _ArbiterReader(self)
        spent = 0.0
        for frame in range(1, frames + 1):
            for sub in range(substeps):
                start = time.perf_counter()
                self.space.step(dt)
                spent += time.perf_counter() - start
                counts[frame] += reader.read(((frame - 1) * substeps + sub + 1) * dt)
            positions[frame], velocities[frame], angles[frame], spins[frame] = self.state()
        w = self.world
        return Trajectory(times=np.arange(frames + 1) / fps, positions=positions, velocities=velocities,
                          angles=angles, angular_velocities=spins, wall_collisions=counts[:, WALL],
                          pair_collisions=counts[:, PAIR], segment_collisions=counts[:, SEGMENT],
                          candidates=np.zeros(frames + 1, np.int64), approximate=np.zeros(frames + 1, bool),
                          world=w, fps=fps, events=reader.events(), method="pymunk", broadphase="",
                          substeps=substeps, profile={"step": spent})

    def asleep(self) -> int:
        """How many bodies Chipmunk has put to sleep."""
        return sum(body.is_sleeping for body in self.bodies)

    def installed_handlers(self) -> int:
        """How many collision handlers the Space holds (0: no callback runs in a step)."""
        return len(getattr(self.space, "_handlers", {}))


class _ArbiterReader:
    """Reads the touching arbiters after a step (pymunk.batch, no callbacks)."""

    def __init__(self, plain: PlainPymunk):
        self.buffer = pymunk.batch.Buffer()
        self.space = plain.space
        kinds = {body.id: (PAIR, i) for i, body in enumerate(plain.bodies)}
        kinds.update({body.id: (WALL, i) for i, body in enumerate(plain.walls)})
        kinds.update({body.id: (SEGMENT, i) for i, body in enumerate(plain.segments)})
        self.kinds = kinds
        self.rows = []

    def read(self, t: float) -> np.ndarray:
        """Counts of contacts begun in this step, by kind; keeps an event per arbiter with impulse."""
        counts = np.zeros(3, np.int64)
        self.buffer.clear()
        pymunk.batch.get_space_arbiters(self.space, _ARBITER_FIELDS, self.buffer)
        ints = np.frombuffer(self.buffer.int_buf(), np.int64).reshape(-1, 4)        # a, b, first, contacts
        floats = np.frombuffer(self.buffer.float_buf(), np.float64).reshape(-1, 6)  # impulse, point a, point b
        for (a, b, first, contacts), (jx, jy, ax, ay, bx, by) in zip(ints.tolist(), floats.tolist()):
            if contacts == 0:          # a cached arbiter of a pair no longer touching
                continue
            kind_a, i = self.kinds[a]
            kind_b, j = self.kinds[b]
            if kind_a != PAIR:         # the particle first
                kind_a, i, kind_b, j = kind_b, j, kind_a, i
            kind = kind_b
            if kind == PAIR and j < i:
                i, j = j, i
            counts[kind] += first
            impulse = math.hypot(jx, jy)
            if impulse > 0.0:
                self.rows.append((t, kind, i, j, impulse, 0.5 * (ax + bx), 0.5 * (ay + by)))
        return counts

    def events(self) -> Events:
        return events_from_rows(self.rows)



def _checked_substeps(scene, substeps) -> int:
    if scene.world is None:
        raise ValueError(f"scene '{scene.name}' is made of panels; run each panel's scene")
    substeps = scene.substeps if substeps is None else substeps
    if int(substeps) != substeps or substeps < 1:
        raise ValueError(f"substeps must be a whole number >= 1, got {substeps}")
    return int(substeps)


def time_plain_pymunk(scene, substeps=None) -> float:
    """Wall seconds of plain pymunk's space.step calls for the whole scene (building the Space,
    a few milliseconds of Python, is not counted)."""
    substeps = _checked_substeps(scene, substeps)
    return PlainPymunk(scene.world).time_steps(scene.fps, scene.frames, substeps)


def simulate_plain_pymunk(scene, substeps=None) -> Trajectory:
    """The scene stepped by plain pymunk, recorded frame by frame (for accuracy, not for timing)."""
    substeps = _checked_substeps(scene, substeps)
    return PlainPymunk(scene.world).record(scene.fps, scene.frames, substeps)
