"""Box2D 2.3 (pybox2d, `pip install box2d`) as a second outside reference: the World's bodies in
a `b2World` set up as a Box2D user would, stepped at the scene's rate, with poses and
velocities read back.

What it sets up
---------------
* one dynamic body per body at the World's position (a polygon's centroid), angle, velocity
  and spin, holding one fixture: a `b2CircleShape` of the World's radius, or a
  `b2PolygonShape` of the World's vertices about the centroid. Mass and moment are set to the
  World's (`b2MassData`), so both engines move the same bodies;
* the box's four sides and the World's segments as static edges;
* friction = the World's μ and restitution = the World's e on every fixture: Box2D mixes a pair
  as sqrt(μ₁μ₂) and max(e₁, e₂), so every contact has exactly the World's materials;
* gravity the World's, everything else Box2D's defaults: 8 velocity and 3 position iterations,
  warm starting, continuous collision against statics, sleeping allowed.

Box2D's own tolerances are part of what it answers and the comparisons allow for them: bodies
rest b2_polygonRadius (0.01) apart, overlaps down to b2_linearSlop (0.005) are left alone, an
impact slower than b2_velocityThreshold (1 unit/s) does not bounce, and no body moves more than
b2_maxTranslation (2 units) a step.
"""
from __future__ import annotations

import numpy as np
import Box2D

from ...core.kinds import CAPSULE, POLYGON


class Box2DWorld:
    """A collisim World in Box2D 2.3; `step(frames)` advances it at `fps`, `substeps` calls of
    `b2World.Step` a frame."""

    def __init__(self, world, fps: float, substeps: int = 1, velocity_iterations: int = 8,
                 position_iterations: int = 3):
        if not np.allclose(world.accelerations, world.gravity):
            raise ValueError("Box2D reference: per-body accelerations are not supported, only gravity")
        if np.any(world.shapes == CAPSULE):
            raise ValueError("Box2D reference: Box2D 2.3 has no capsule; compare a world with capsules against pymunk")
        self.dt = 1.0 / (fps * substeps)
        self.substeps, self.iterations = substeps, (velocity_iterations, position_iterations)
        self.b2 = Box2D.b2World(gravity=tuple(float(g) for g in world.gravity), doSleep=True)
        self._add_statics(world)
        self.bodies = [self._add_body(world, i) for i in range(world.n)]

    def _add_statics(self, world):
        x0, y0, x1, y1 = (float(v) for v in world.box)
        corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
        edges = [(corners[k], corners[(k + 1) % 4]) for k in range(4)]
        edges += [((float(s[0]), float(s[1])), (float(s[2]), float(s[3]))) for s in world.segments]
        ground = self.b2.CreateStaticBody()
        for a, b in edges:
            ground.CreateEdgeFixture(vertices=[a, b], friction=float(world.friction),
                                     restitution=float(world.restitution))

    def _add_body(self, world, i: int):
        body = self.b2.CreateDynamicBody(position=tuple(float(v) for v in world.positions[i]),
                                         angle=float(world.angles[i]))
        material = dict(density=1.0, friction=float(world.friction), restitution=float(world.restitution))
        if world.shapes[i] == POLYGON:
            vertices = world.body_vertices[world.vertex_start[i]:world.vertex_start[i + 1]]
            body.CreatePolygonFixture(vertices=[tuple(float(c) for c in v) for v in vertices], **material)
        else:
            body.CreateCircleFixture(radius=float(world.radii[i]), **material)
        body.massData = Box2D.b2MassData(mass=float(world.masses[i]), center=(0.0, 0.0), I=float(world.inertias[i]))
        body.linearVelocity = tuple(float(v) for v in world.velocities[i])
        body.angularVelocity = float(world.angular_velocities[i])
        return body

    def step(self, frames: int = 1):
        for _ in range(frames * self.substeps):
            self.b2.Step(self.dt, *self.iterations)

    @property
    def positions(self) -> np.ndarray:
        return np.array([tuple(b.position) for b in self.bodies])

    @property
    def velocities(self) -> np.ndarray:
        return np.array([tuple(b.linearVelocity) for b in self.bodies])

    @property
    def angles(self) -> np.ndarray:
        return np.array([b.angle for b in self.bodies])

    @property
    def angular_velocities(self) -> np.ndarray:
        return np.array([b.angularVelocity for b in self.bodies])
