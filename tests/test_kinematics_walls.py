"""Particle dynamics and discrete wall collisions against closed forms and invariants."""
import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import collisim
from conftest import statics_step


def simulate_one(position, velocity, gravity=(0.0, 0.0), box=(-1e6, -1e6, 1e6, 1e6), fps=60, seconds=2.0,
                 substeps=1, restitution=1.0, radius=0.5):
    world = collisim.World(positions=[position], velocities=[velocity], radii=radius, box=box,
                           gravity=gravity, restitution=restitution)
    return collisim.simulate(collisim.Scene(world=world, fps=fps, seconds=seconds, substeps=substeps))


@pytest.mark.parametrize("substeps", [1, 3])
def test_kinematics_match_the_closed_form_at_every_frame(substeps):
    p0, v0, g = np.array([1.5, -2.0]), np.array([3.0, 7.0]), np.array([0.3, -9.81])
    traj = simulate_one(p0, v0, gravity=g, fps=24, seconds=3.0, substeps=substeps)
    t = traj.times[:, None]
    assert traj.times[-1] == pytest.approx(3.0)
    assert len(traj.times) == 24 * 3 + 1
    np.testing.assert_allclose(traj.positions[:, 0], p0 + v0 * t + 0.5 * g * t ** 2, rtol=1e-12, atol=1e-11)
    np.testing.assert_allclose(traj.velocities[:, 0], v0 + g * t, rtol=1e-12, atol=1e-12)
    assert traj.collisions.sum() == 0


@given(t=st.floats(0.01, 5.0), fps=st.sampled_from([7, 24, 60, 144]))
@settings(max_examples=25, deadline=None)
def test_kinematics_at_arbitrary_times(t, fps):
    seconds = max(round(t * fps), 1) / fps
    p0, v0, g = np.array([0.0, 0.0]), np.array([-4.0, 2.5]), np.array([0.0, -9.81])
    traj = simulate_one(p0, v0, gravity=g, fps=fps, seconds=seconds)
    T = traj.times[-1]
    np.testing.assert_allclose(traj.positions[-1, 0], p0 + v0 * T + 0.5 * g * T * T, rtol=1e-11, atol=1e-11)


def wall_step(position, velocity, box=(0.0, 0.0, 10.0, 10.0), radius=1.0, restitution=1.0):
    pos, vel = np.array([position], float), np.array([velocity], float)
    counts, events = statics_step(pos, vel, [radius], [2.0], box, restitution=restitution)
    return pos[0], vel[0], counts[0], (events.i, events.j, events.impulse, events.point)


def test_wall_hit_reflects_overshoot_and_flips_normal_velocity():
    pos, vel, hits, (particle, wall, impulse, point) = wall_step([0.7, 5.0], [-3.0, 1.0])
    np.testing.assert_allclose(pos, [1.3, 5.0])          # 0.3 past the wall, reflected to 0.3 inside
    np.testing.assert_allclose(vel, [3.0, 1.0])
    assert hits == 1 and wall[0] == 0 and impulse[0] == pytest.approx(2.0 * 2 * 3.0)
    np.testing.assert_allclose(point[0], [0.0, 5.0])


def test_particle_leaving_the_wall_is_not_flipped_back():
    pos, vel, hits, _ = wall_step([0.9, 5.0], [2.0, 0.0])   # overlapping the left wall but leaving
    assert hits == 0 and vel[0] == 2.0 and pos[0] == 1.0   # put on the wall, never sticks


@given(x=st.floats(-50, 60), y=st.floats(-50, 60), vx=st.floats(-1e3, 1e3), vy=st.floats(-1e3, 1e3),
       e=st.sampled_from([1.0, 0.8, 0.0]))
@settings(max_examples=200, deadline=None)
def test_wall_response_ends_inside_and_keeps_speed_at_e1(x, y, vx, vy, e):
    pos, vel, hits, _ = wall_step([x, y], [vx, vy], restitution=e)
    assert np.all(pos >= 1.0) and np.all(pos <= 9.0)
    if e == 1.0:
        assert np.hypot(*vel) == pytest.approx(np.hypot(vx, vy), rel=1e-15)
    assert np.all(np.abs(vel) <= np.abs([vx, vy]) + 1e-12)


def test_restitution_scales_the_rebound_speed():
    _, vel, _, _ = wall_step([5.0, 0.8], [0.0, -4.0], restitution=0.5)
    assert vel[1] == pytest.approx(2.0)


@pytest.mark.parametrize("speed", [50.0, 1e6])
def test_fast_particle_never_leaves_the_box_in_100000_frames(speed):
    angle = 0.7234
    traj = simulate_one([3.0, 4.0], [speed * np.cos(angle), speed * np.sin(angle)], box=(0, 0, 16, 9),
                        fps=60, seconds=100_000 / 60, radius=0.4)
    assert traj.frames == 100_000
    p = traj.positions[:, 0]
    assert np.all(p - 0.4 >= 0.0) and np.all(p[:, 0] + 0.4 <= 16.0) and np.all(p[:, 1] + 0.4 <= 9.0)
    speeds = np.hypot(*traj.velocities[:, 0].T)
    np.testing.assert_allclose(speeds, speed, rtol=1e-12)   # e = 1 keeps the speed
    assert traj.wall_collisions.sum() > 0


@pytest.mark.parametrize("restitution", [1.0, 0.7])
def test_bounce_under_gravity_keeps_energy_consistent(restitution):
    g = 9.81
    traj = simulate_one([5.0, 8.0], [1.3, 0.0], gravity=(0, -g), box=(0, 0, 10, 10), fps=60, seconds=60,
                        restitution=restitution)
    p, v = traj.positions[:, 0], traj.velocities[:, 0]
    assert np.all(p >= 0.5 - 1e-12) and np.all(p <= 9.5 + 1e-12)
    energy = 0.5 * np.sum(v ** 2, axis=1) + g * p[:, 1]
    if restitution == 1.0:
        # the reflected overshoot keeps speed and height consistent: no energy is made or lost
        np.testing.assert_allclose(energy, np.full_like(energy, energy[0]), rtol=1e-9)
    else:
        # every floor bounce keeps e² of the vertical kinetic energy: energy only decreases
        assert np.all(np.diff(energy) <= 1e-9 * energy[0]) and energy[-1] < 0.2 * energy[0]


def test_wall_impulses_give_the_exact_pressure_of_a_single_particle():
    # One particle bouncing between two walls at speed u: each hit delivers 2·m·u.
    traj = simulate_one([2.0, 5.0], [7.0, 0.0], box=(0, 0, 10, 10), fps=50, seconds=10.0, radius=0.5)
    hits = traj.events.kind == 0
    np.testing.assert_allclose(traj.events.impulse[hits], 2 * np.pi * 0.25 * 7.0, rtol=1e-12)
    assert hits.sum() == pytest.approx(7.0 * 10 / 9.0, abs=1)


@pytest.mark.parametrize("speed, radius", [(1e13, 1.0), (50.0, 5.0 - 5e-13)])
def test_elastic_wall_response_is_bounded_at_any_speed_and_gap(speed, radius):
    # 1e13 units/s crosses the box 1e11 times a frame; a radius leaving a 1e-12 gap bounces 1e13 times:
    # the free elastic flight is folded in O(1), exactly in the box, energy exact
    world = collisim.World([[5.0, 5.0]], velocities=[[speed, 0.3 * speed]], radii=radius)
    traj = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=0.5))
    p, r = traj.positions[:, 0], radius
    assert np.all((p - r >= -1e-9) & (p + r <= 10 + 1e-9))
    np.testing.assert_array_equal(np.abs(traj.velocities[-1, 0]), [speed, 0.3 * speed])
    assert traj.wall_collisions.sum() > 1e6


def test_a_speed_the_frame_rate_cannot_represent_is_one_clear_error():
    world = collisim.World([[5.0, 5.0]], velocities=[[0.0, 1e13]], radii=1.0, gravity=(0, -9.8))
    with pytest.raises(ValueError, match="would cross the box more than 10 000 times in one step"):
        collisim.simulate(collisim.Scene(world=world, fps=60, seconds=0.1))


@pytest.mark.parametrize("speed", [1e20, 1e30])
def test_an_elastic_speed_too_fast_to_fold_is_one_clear_error(speed):
    # 1e20 units/s crosses the box 2e17 times a step: more than the fold can count (its place in
    # the box would be rounding noise); at 1e30 the count overflowed and the body left the box
    world = collisim.World([[5.0, 5.0]], velocities=[[speed, 0.3 * speed]], radii=1.0)
    with pytest.raises(ValueError, match="would cross the box more than 1e12 times in one step"):
        collisim.simulate(collisim.Scene(world=world, fps=60, seconds=0.1))
