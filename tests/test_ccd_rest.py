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


def test_tc_model_makes_collisions_within_tc_of_the_last_elastic():
    from collisim.engine.ccd.events import simulate_events
    # a ball between two walls, e = 0.5: its first hit halves its speed, and with tc = 10 s every
    # later hit (each within 10 s of the previous one) is elastic
    common = ([[5.0, 5.0]], [[8.0, 0.0]], (0.0, 0.0), [0.5], [1.0], (0.0, 0.0, 10.0, 10.0), 0.5, None, 0.1, 80)
    with_tc = simulate_events(*common, tc=10.0)
    assert len(with_tc.time) >= 4
    np.testing.assert_allclose(np.abs(with_tc.velocities[-1, 0, 0]), 4.0, rtol=1e-12)
    without = simulate_events(*common)
    assert np.abs(without.velocities[-1, 0, 0]) <= 1.0   # 8 -> 4 -> 2 -> 1: every hit halves it


def test_contact_model_parameters_are_checked():
    world = collisim.World(positions=[[5.0, 1.0]], box=(0, 0, 10, 10), gravity=(0, -G), restitution=0.5)
    with pytest.raises(ValueError, match="rest_speed"):
        collisim.Scene(world=world, method="ccd", rest_speed=-1.0)
    with pytest.raises(ValueError, match="tc"):
        collisim.Scene(world=world, method="ccd", tc="1")


@pytest.mark.slow
@pytest.mark.xfail(reason="sleeping is experimental: from frame 70 two balls overlap by up to 8 % of r "
                          "(engine/ccd/sleep.py, status)", strict=False)
def test_a_small_inelastic_pile_falls_asleep_without_overlap():
    """24 balls, e = 0.5, dropped into a box 6 diameters wide: by 5 s every one is asleep."""
    rng = np.random.default_rng(3)
    n = 24
    x = (np.arange(n) % 6 + 0.5) * (6.0 / 6) + rng.uniform(-0.05, 0.05, n)
    y = 1.0 + (np.arange(n) // 6) * 1.2
    world = collisim.World(np.column_stack([x, y]), radii=0.45, box=(0, 0, 6, 8), gravity=(0, -G), restitution=0.5)
    with pytest.warns(UserWarning, match="approximate"):   # not yet free of event storms (see below)
        traj = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=6.0, method="ccd", rest_speed=0.094))
    # Measured: 13 of 360 frames go over the event budget while the pile settles (inelastic
    # collapse among awake bodies); they keep their exact state and are flagged.
    assert traj.approximate.sum() <= 40
    # asleep: every body still, exactly
    assert np.all(traj.velocities[-30:] == 0.0)
    p = traj.positions[-1]
    d = np.hypot(*(p[:, None] - p[None]).T)[np.triu_indices(n, 1)]
    assert d.min() >= 0.9 * (1 - 1e-9)
