"""The same World stepped by pymunk (Chipmunk2D), recorded as a collisim Trajectory.

pymunk is the outside reference: a widely used impulse-based engine, set up as close to
collisim's physics as it can be, so that where the two agree neither is likely wrong, and where
they differ the difference can be traced to one of the items below.

What the mirror sets up
-----------------------
* one dynamic body per body of the World (reference/bodies.py): a pymunk.Circle, or a
  pymunk.Poly of the same vertices about the centroid, with the World's mass, angle and spin.
  Moment: the World's (World.inertias) for a polygon, and for a circle when friction acts; a
  frictionless circle gets an *infinite* moment, since nothing can turn it in collisim, while
  in Chipmunk round-off in the contact frame would turn translational kinetic energy into spin;
* friction: Chipmunk multiplies the two shapes' frictions, so every shape gets sqrt(μ) and each
  contact's product is the World's μ (as restitution, below);
* restitution: Chipmunk's contact restitution is the *product* of the two shapes' elasticities.
  The usual recipe (e on particles, 1 on walls) gives e against walls but e² between two
  particles; the mirror sets sqrt(e) on *every* shape, so each product, particle-particle,
  particle-wall and particle-segment, is exactly e (one function, _per_shape, for e and μ);
* the box walls are thick static segments (a segment of radius R, R = the box's larger side,
  whose surface lies on the box edge and which runs R past each corner). Chipmunk has no half
  planes; a thin wall would let a particle that moves more than its radius in a step tunnel out
  of the box, while collisim's walls keep every particle in, so thick walls keep the comparison
  about pair and segment physics;
* thin segments (world.segments) are static segments of radius 0: two-sided, with point caps,
  as collisim's;
* gravity as space.gravity (or a per-body velocity function for per-particle accelerations),
  damping 1 (no velocity decay), sleeping off;
* steps of dt = 1 / (fps × substeps).

Settings chosen to make Chipmunk as exact as it can be
-----------------------------------------------------
* collision_slop = 1e-3 × the smallest radius. Chipmunk only pushes apart overlaps deeper than
  the slop; its default 0.1 world units is half the radius of particles_250's small circles.
* collision_bias: the fraction of an overlap *left* after one second. The default corrects 10 %
  per 1/60 s; the mirror removes the whole overlap in one step (bias ~0), as collisim's discrete
  response does. The correction runs through a separate "bias velocity" that moves positions
  only, so it never changes kinetic energy, but it does move particles (potential energy under
  gravity, and where the next contacts happen).
* iterations = 30 (default 10): the solver is iterative, and simultaneous contacts need
  iterations to converge.

These settings matter (measured): with Chipmunk's default bias and the small slop the gas of
particles_250 drifts 3e-5 in energy over 10 s instead of 3e-14, and single_bounce ends 1 % off
in energy with the default slop instead of 7e-5.

What cannot be matched, and why
-------------------------------
* Integration: Chipmunk moves positions with the velocity of the end of the previous step,
  then adds gravity to the velocity (semi-implicit Euler): p_k = exact − ½·g·t·dt, a lag of half
  a step in time per fall. collisim integrates constant acceleration exactly.
* Detection is discrete and there is no continuous collision detection: a pair or a segment is
  seen only if the circles overlap at the end of a step, so fast particles tunnel exactly where
  collisim's discrete method tunnels (the mirror keeps this on purpose; tests rely on it).
* Response timing: the bounce target e·v_n is taken from the velocity *before* this step's
  gravity, and that step's gravity is then absorbed by the contact impulse; collisim reflects the
  velocity at the contact instant. Rebound speeds differ by up to g·dt.
* Overlap removal is deferred: an overlap found in one step is pushed apart by the bias velocity
  during the *next* position update, and only beyond the slop. collisim separates at once.
* Simultaneous contacts: Chipmunk solves all contacts of a step together by projected
  Gauss-Seidel with restitution targets per contact; for three or more bodies in contact at
  once the result is not a sequence of two-body collisions and need not conserve kinetic
  energy exactly. collisim's discrete method resolves contacts one pair after another, in
  sorted order; its ccd solves the contacts of one instant together (also by projected
  Gauss-Seidel, to convergence), and contacts at different instants one after another. An
  isolated contact is solved exactly by both.
* Warm starting (collision_persistence): an arbiter that is touching again within
  collision_persistence steps starts from its cached impulse. The accumulated-impulse clamp
  removes a cached impulse that is no longer needed, so after the iterations converge an
  isolated contact is unaffected, but in clusters the cache changes the converged solution.
* Chipmunk stores some settings as 32-bit floats on some builds (the default slop reads
  0.10000000149), and its spatial index is its own; neither matters above round-off here.

Events: begin callbacks count contacts (a pair that keeps touching for several steps counts
once; one that separates and touches again counts twice), post_solve callbacks give impulses
(`arbiter.total_impulse`, one row per step with a non-zero impulse) with the contact point half
way between the two surfaces.
"""
from __future__ import annotations

import math
import time

import numpy as np
import pymunk
import pymunk.batch

from ...core.kinds import CAPSULE, PAIR, POLYGON, SEGMENT, WALL
from ...model.trajectory import Events, Trajectory
from .bodies import add_body, events_from_rows, read_state

ITERATIONS = 30
SLOP_PER_RADIUS = 1e-3
# Fraction of an overlap left after one second: 1e-12 leaves 1e-12^(1/60) ~ 1e-5 % after a
# 60 fps step, i.e. the whole overlap is removed in the next step (0 itself is "not recommended
# for stability" by pymunk, and pow(0, dt) gives the same).
COLLISION_BIAS = 1e-12
COLLISION_PERSISTENCE = 3   # Chipmunk's default: the cache only matters for resting contacts

PARTICLE_TYPE, WALL_TYPE, SEGMENT_TYPE = 1, 2, 3


def simulate_pymunk(scene, substeps=None, iterations=None) -> Trajectory:
    """Step scene.world with pymunk at fps × substeps and sample every frame.

    substeps: steps per frame (default: the scene's); iterations: solver iterations (default 30).
    Returns a Trajectory like collisim.simulate's for a single-world scene, method "pymunk".
    """
    if scene.world is None:
        raise ValueError(f"scene '{scene.name}' is made of panels; mirror each panel's scene")
    substeps = scene.substeps if substeps is None else substeps
    iterations = ITERATIONS if iterations is None else iterations
    if int(substeps) != substeps or substeps < 1:
        raise ValueError(f"substeps must be a whole number >= 1, got {substeps}")
    if int(iterations) != iterations or iterations < 1:
        raise ValueError(f"iterations must be a whole number >= 1, got {iterations}")
    mirror = Mirror(scene.world, int(iterations))
    return mirror.run(scene.fps, scene.frames, int(substeps))


class Mirror:
    """A pymunk Space equivalent to a World, with callbacks that record collisions."""

    def __init__(self, world, iterations: int = ITERATIONS):
        self.world = world
        self.space = _new_space(world, iterations)
        self.recorder = _Recorder()
        self.bodies = _add_particles(self.space, world, self.recorder)
        _add_walls(self.space, world, self.recorder)
        _add_segments(self.space, world, self.recorder)
        for other, kind in ((PARTICLE_TYPE, PAIR), (WALL_TYPE, WALL), (SEGMENT_TYPE, SEGMENT)):
            self.space.on_collision(PARTICLE_TYPE, other, begin=self.recorder.begin,
                                    post_solve=self.recorder.post_solve, data=kind)
        self._buffer = pymunk.batch.Buffer()

    def state(self) -> tuple:
        """(positions (n, 2), velocities (n, 2), angles (n,), angular velocities (n,))."""
        return read_state(self.space, self.world.n, self._buffer)

    def run(self, fps: float, frames: int, substeps: int) -> Trajectory:
        n, dt = self.world.n, 1.0 / fps / substeps
        positions, velocities = np.empty((frames + 1, n, 2)), np.empty((frames + 1, n, 2))
        angles, spins = np.empty((frames + 1, n)), np.empty((frames + 1, n))
        collisions = np.zeros((frames + 1, 3), np.int64)
        positions[0], velocities[0], angles[0], spins[0] = self.state()
        spent = 0.0
        for frame in range(1, frames + 1):
            start = time.perf_counter()
            for step in range(substeps):
                self.recorder.time = ((frame - 1) * substeps + step + 1) * dt
                self.space.step(dt)
            spent += time.perf_counter() - start
            collisions[frame] = self.recorder.take_counts()
            positions[frame], velocities[frame], angles[frame], spins[frame] = self.state()
        w = self.world
        return Trajectory(times=np.arange(frames + 1) / fps, positions=positions, velocities=velocities,
                          angles=angles, angular_velocities=spins, wall_collisions=collisions[:, WALL],
                          pair_collisions=collisions[:, PAIR], segment_collisions=collisions[:, SEGMENT],
                          candidates=np.zeros(frames + 1, np.int64), approximate=np.zeros(frames + 1, bool), world=w,
                          fps=fps,
                          events=self.recorder.events(), method="pymunk", broadphase="",
                          substeps=substeps, profile={"step": spent})


class _Recorder:
    """Collision callbacks: begin counts contacts, post_solve records impulses."""

    def __init__(self):
        self.time = 0.0
        self.index = {}          # shape -> particle, wall or segment index
        self._counts = np.zeros(3, np.int64)
        self._rows = []

    def begin(self, arbiter, space, kind) -> None:
        self._counts[kind] += 1

    def post_solve(self, arbiter, space, kind) -> None:
        impulse = arbiter.total_impulse.length
        if impulse <= 0.0:
            return
        particle, other = arbiter.shapes           # ordered as the handler's types
        i, j = self.index[particle], self.index[other]
        if kind == PAIR and j < i:
            i, j = j, i
        contact = arbiter.contact_point_set.points[0]
        x = 0.5 * (contact.point_a.x + contact.point_b.x)
        y = 0.5 * (contact.point_a.y + contact.point_b.y)
        self._rows.append((self.time, kind, i, j, impulse, x, y))

    def take_counts(self) -> np.ndarray:
        counts, self._counts = self._counts, np.zeros(3, np.int64)
        return counts

    def events(self) -> Events:
        return events_from_rows(self._rows)


def _new_space(world, iterations: int) -> pymunk.Space:
    space = pymunk.Space()
    space.iterations = iterations
    space.damping = float(world.damping)
    smallest = float(world.radii.min()) if world.n else 1.0
    space.collision_slop = SLOP_PER_RADIUS * smallest
    space.collision_bias = COLLISION_BIAS
    space.collision_persistence = COLLISION_PERSISTENCE
    if world.uniform_acceleration:
        space.gravity = tuple(world.accelerations[0]) if world.n else tuple(world.gravity)
    return space


def _per_shape(value: float) -> float:
    """Chipmunk multiplies the two shapes' elasticities (and frictions): sqrt(value) on every
    shape makes each contact's product the World's value (e on particles and 1 on walls would
    give e² between two particles)."""
    return math.sqrt(value)


def _moments(world) -> np.ndarray:
    """Each body's moment: the World's, but infinite for a circle no friction can turn (see the
    module docstring)."""
    spins = (world.shapes == POLYGON) | (world.shapes == CAPSULE) | (world.friction > 0.0)
    return np.where(spins, world.inertias, math.inf)


def _add_particles(space, world, recorder) -> list:
    bodies = []
    uniform = world.uniform_acceleration
    for i, moment in enumerate(_moments(world)):
        body, shape = add_body(space, world, i, moment, uniform)
        _set_material(shape, PARTICLE_TYPE, world)
        recorder.index[shape] = i
        bodies.append(body)
    return bodies



def _add_walls(space, world, recorder) -> None:
    """The box as four thick static segments, in collisim's wall order: left, right, bottom, top."""
    xmin, ymin, xmax, ymax = (float(v) for v in world.box)
    thick = max(xmax - xmin, ymax - ymin)
    reach = 2.0 * thick   # past the corners, so a corner is two flat faces
    centre_lines = [((xmin - thick, ymin - reach), (xmin - thick, ymax + reach)),
                    ((xmax + thick, ymin - reach), (xmax + thick, ymax + reach)),
                    ((xmin - reach, ymin - thick), (xmax + reach, ymin - thick)),
                    ((xmin - reach, ymax + thick), (xmax + reach, ymax + thick))]
    for index, (a, b) in enumerate(centre_lines):
        wall = pymunk.Segment(space.static_body, a, b, thick)
        _set_material(wall, WALL_TYPE, world)
        space.add(wall)
        recorder.index[wall] = index


def _add_segments(space, world, recorder) -> None:
    for index, (x0, y0, x1, y1) in enumerate(world.level_segments):   # the map's exact outline too
        segment = pymunk.Segment(space.static_body, (float(x0), float(y0)), (float(x1), float(y1)), 0.0)
        _set_material(segment, SEGMENT_TYPE, world)
        space.add(segment)
        recorder.index[segment] = index


def _set_material(shape, collision_type: int, world) -> None:
    """Every shape's material, walls and segments included: see _per_shape."""
    shape.collision_type = collision_type
    shape.elasticity = _per_shape(world.restitution)
    shape.friction = _per_shape(world.friction)
