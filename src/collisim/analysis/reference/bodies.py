"""The World's bodies as pymunk bodies and shapes, and their state read back: shared by the
comparison mirror and plain pymunk, which differ only in their settings and materials.

Each body is a dynamic `pymunk.Body(mass, moment)` at the World's position (a polygon's
centroid, which is its centre of mass), velocity, angle and spin, holding one shape: a
`pymunk.Circle` of the World's radius, or a `pymunk.Poly` (radius 0) of the World's vertices
in the body frame about the centroid (World.body_vertices), so pymunk's centre of gravity, the
body's origin, is the World's. Mass and moment are the World's (World.masses, World.inertias),
set on the body; the shapes carry no density of their own.
"""
from __future__ import annotations

import numpy as np
import pymunk
import pymunk.batch

from ...core.kinds import CAPSULE, POLYGON
from ...model.trajectory import Events

_STATE_FIELDS = (pymunk.batch.BodyFields.POSITION | pymunk.batch.BodyFields.ANGLE
                 | pymunk.batch.BodyFields.VELOCITY | pymunk.batch.BodyFields.ANGULAR_VELOCITY)


def add_body(space: pymunk.Space, world, i: int, moment: float, uniform: bool) -> tuple:
    """Body i of the World added to `space` with the given moment: (body, shape). uniform:
    world.uniform_acceleration, which the caller reads once (it looks at every body)."""
    body = pymunk.Body(float(world.masses[i]), float(moment))
    body.position = tuple(float(v) for v in world.positions[i])
    body.velocity = tuple(float(v) for v in world.velocities[i])
    body.angle = float(world.angles[i])
    body.angular_velocity = float(world.angular_velocities[i])
    if world.shapes[i] == POLYGON:
        vertices = world.body_vertices[world.vertex_start[i]:world.vertex_start[i + 1]]
        shape = pymunk.Poly(body, [tuple(float(v) for v in vertex) for vertex in vertices], radius=0.0)
    elif world.shapes[i] == CAPSULE:
        a, b = world.body_vertices[world.vertex_start[i]:world.vertex_start[i] + 2]
        shape = pymunk.Segment(body, tuple(float(v) for v in a), tuple(float(v) for v in b),
                               float(world.capsule_radii[i]))
    else:
        shape = pymunk.Circle(body, float(world.radii[i]))
    if not uniform:   # each body follows its own acceleration, not the space's gravity
        body.velocity_func = _constant_acceleration(tuple(float(a) for a in world.accelerations[i]))
    space.add(body, shape)
    return body, shape


def _constant_acceleration(acceleration):
    """A velocity function that applies this particle's own acceleration instead of gravity."""
    def update(body, gravity, damping, dt):
        pymunk.Body.update_velocity(body, acceleration, damping, dt)
    return update


def events_from_rows(rows: list) -> Events:
    """Events from recorded (time, kind, i, j, impulse, x, y) tuples, in canonical order."""
    if not rows:
        return Events.empty()
    t, kind, i, j, impulse, x, y = (np.array(column) for column in zip(*rows))
    return Events.concatenate([Events(t.astype(np.float64), kind.astype(np.int8), i.astype(np.intp),
                                      j.astype(np.intp), impulse.astype(np.float64),
                                      np.column_stack([x, y]).astype(np.float64))])


def read_state(space: pymunk.Space, n: int, buffer: pymunk.batch.Buffer) -> tuple:
    """(positions (n, 2), velocities (n, 2), angles (n,), angular velocities (n,)) of the first n
    dynamic bodies in the order they were added, read in one batch call."""
    buffer.clear()
    pymunk.batch.get_space_bodies(space, _STATE_FIELDS, buffer)
    # one row (x, y, angle, vx, vy, spin) per dynamic body: the fields in their flag order
    rows = np.frombuffer(buffer.float_buf(), np.float64)[:6 * n].reshape(n, 6)
    return rows[:, 0:2].copy(), rows[:, 3:5].copy(), rows[:, 2].copy(), rows[:, 5].copy()
