"""ccd under gravity: bodies at rest, the supports that carry them, and what they log."""
import math

import numpy as np
import pytest

import collisim
from collisim.analysis import metrics
from collisim.engine.ccd.events import simulate_events
from collisim.geometry.segment import segment_contact

G = 9.81


def ccd(positions, radius=0.5, restitution=0.5, seconds=3.0, segments=None, velocities=None):
    world = collisim.World(positions=positions, velocities=velocities, radii=radius, box=(0, 0, 10, 10),
                           gravity=(0, -G), restitution=restitution, segments=segments)
    return world, collisim.simulate(collisim.Scene(world=world, fps=60, seconds=seconds, method="ccd"))


def test_the_floor_carries_the_weight_of_a_body_at_rest_on_it():
    world, traj = ccd([[5.0, 0.5]])
    perimeter = 2 * (10 + 10)
    weight = world.masses[0] * G
    assert metrics.wall_pressure(traj) * perimeter == pytest.approx(weight, rel=1e-9)
    # m·g·dt each frame, on the floor, under the body, not counted as a collision
    floor = traj.events.impulse[traj.events.j == 2]
    np.testing.assert_allclose(floor, weight / 60, rtol=1e-9)
    assert len(floor) == traj.frames and traj.wall_collisions.sum() == 0
    np.testing.assert_allclose(traj.events.point, np.tile([5.0, 0.0], (traj.frames, 1)))


def test_bounces_then_rest_give_the_floor_the_momentum_balance():
    # the floor's impulse over [0, T] is m g T + m (v_y(T) - v_y(0)): bounces and rest together
    world, traj = ccd([[5.0, 6.0]], restitution=0.6, seconds=6.0)
    assert traj.velocities[-1, 0, 1] == 0.0 and traj.positions[-1, 0, 1] == 0.5   # at rest by then
    duration = traj.times[-1]
    floor = traj.events.impulse[(traj.events.kind == 0) & (traj.events.j == 2)].sum()
    assert floor == pytest.approx(world.masses[0] * G * duration, rel=1e-9)


def test_a_segment_carries_a_ball_at_rest_and_a_vee_carries_a_wedged_ball():
    shelf = [[2.0, 4.0, 8.0, 4.0]]
    world, traj = ccd([[5.0, 4.5]], segments=shelf)
    impulse = traj.events.impulse[traj.events.kind == 2].sum()
    assert impulse == pytest.approx(world.masses[0] * G * traj.times[-1], rel=1e-9)

    vee = np.array([[1.0, 6.0, 5.0, 2.0], [5.0, 2.0, 9.0, 6.0]])
    world, traj = ccd([[3.0, 8.0]], segments=vee, velocities=[[0.3, 0.0]], seconds=10.0)
    assert np.all(traj.velocities[-1] == 0.0)
    # from when it is wedged on, the two sides' impulses add up to the weight: m g per second
    late = (traj.events.kind == 2) & (traj.events.time > 8.0)
    lift = 0.0
    for j, impulse, point in zip(traj.events.j[late], traj.events.impulse[late], traj.events.point[late]):
        ny = segment_contact(*traj.positions[-1, 0], vee[j])[1]
        lift += impulse * ny
    assert lift == pytest.approx(world.masses[0] * G * 2.0, rel=1e-9)
