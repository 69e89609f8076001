"""Box2D 2.3 as a user would run it: the second speed baseline of `collisim bench polygons`.

Built as Box2D's manual builds a world (pybox2d, `pip install box2d`): a `b2World` with the
World's gravity and Box2D's defaults (sleeping allowed, warm starting, continuous collision of
dynamic bodies against static ones); one static ground body holding the box's four walls and
the World's segments as edge shapes; one dynamic body a body, at the World's position (a
polygon's centroid), angle, velocity and spin, holding one fixture — a `b2PolygonShape` of the
World's vertices about the centroid, or a `b2CircleShape` of its radius — whose density is the
body's mass over its area, so Box2D computes the World's mass and (for uniform density) moment
of inertia. A step is `world.Step(dt, 8, 3)`: the velocity and position iterations the manual
recommends.

Materials: Box2D mixes a contact's friction as √(μa·μb) and its restitution as max(ea, eb), so
every fixture, walls included, gets the World's μ and e and every pair meets with exactly those.

Box2D is optional: `missing()` says why it cannot run (a benchmark prints that line instead).
Box2D keeps its state in float32 and holds polygons of at most 8 vertices.
"""
from __future__ import annotations

import time
import warnings

import numpy as np

from ...core.kinds import POLYGON

VELOCITY_ITERATIONS = 8
POSITION_ITERATIONS = 3
NOT_INSTALLED = "Box2D 2.3 not installed (pip install box2d)"


def missing() -> str | None:
    """None when Box2D 2.3 can be imported, else the line to print instead of its figures."""
    try:
        box2d()
    except ImportError:
        return NOT_INSTALLED
    return None


def box2d():
    """The Box2D module, imported without the notes its SWIG types give Python 3.12's import
    ("builtin type SwigPyPacked has no __module__ attribute")."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        import Box2D
    return Box2D


class PlainBox2D:
    """A default Box2D 2.3 world holding a collisim World (see the module docstring)."""

    def __init__(self, world):
        b2 = box2d()
        self.world = world
        mu, e = float(world.friction), float(world.restitution)
        if not world.uniform_acceleration:
            raise ValueError("Box2D's baseline needs one gravity for every body")
        gravity = world.accelerations[0] if world.n else world.gravity
        self.b2 = b2.b2World(gravity=tuple(float(g) for g in gravity))
        xmin, ymin, xmax, ymax = (float(v) for v in world.box)
        edges = [(xmin, ymin, xmin, ymax), (xmax, ymin, xmax, ymax), (xmin, ymin, xmax, ymin),
                 (xmin, ymax, xmax, ymax), *(tuple(float(v) for v in s) for s in world.level_segments)]
        ground = self.b2.CreateStaticBody(shapes=[b2.b2EdgeShape(vertices=[(x0, y0), (x1, y1)])
                                                  for x0, y0, x1, y1 in edges])
        for fixture in ground.fixtures:
            fixture.friction, fixture.restitution = mu, e
        self.bodies = [self._add_body(i, mu, e) for i in range(world.n)]

    def _add_body(self, i: int, mu: float, e: float):
        w = self.world
        body = self.b2.CreateDynamicBody(position=tuple(float(v) for v in w.positions[i]), angle=float(w.angles[i]),
                                         linearVelocity=tuple(float(v) for v in w.velocities[i]),
                                         angularVelocity=float(w.angular_velocities[i]))
        if w.shapes[i] == POLYGON:
            vertices = w.body_vertices[w.vertex_start[i]:w.vertex_start[i + 1]]
            x, y = vertices[:, 0], vertices[:, 1]
            area = 0.5 * abs(float(np.dot(x, np.roll(y, -1)) - np.dot(y, np.roll(x, -1))))
            body.CreatePolygonFixture(vertices=[tuple(float(v) for v in vertex) for vertex in vertices],
                                      density=float(w.masses[i]) / area, friction=mu, restitution=e)
        else:
            radius = float(w.radii[i])
            body.CreateCircleFixture(radius=radius, density=float(w.masses[i]) / (np.pi * radius ** 2),
                                     friction=mu, restitution=e)
        return body

    def time_steps(self, fps: float, frames: int) -> float:
        """Advance `frames` steps of 1/fps: wall seconds spent in world.Step alone."""
        step, dt = self.b2.Step, 1.0 / fps
        start = time.perf_counter()
        for _ in range(frames):
            step(dt, VELOCITY_ITERATIONS, POSITION_ITERATIONS)
        return time.perf_counter() - start

    def positions(self) -> np.ndarray:
        """(n, 2) centres of mass in the World's order."""
        return np.array([tuple(body.worldCenter) for body in self.bodies]).reshape(-1, 2)

    def asleep(self) -> int:
        """How many bodies Box2D has put to sleep."""
        return sum(not body.awake for body in self.bodies)
