"""Method `ccd`: the exact event-driven simulation (collisim.ccd.events)."""
import math

import numpy as np
import pytest

from collisim.engine.ccd.events import simulate_events

NO_GRAVITY = (0.0, 0.0)


def run(positions, velocities, radii=1.0, masses=1.0, box=(0.0, 0.0, 10.0, 10.0), gravity=NO_GRAVITY,
        restitution=1.0, segments=None, frame_dt=0.1, n_frames=10, **options):
    positions = np.asarray(positions, dtype=np.float64)
    n = len(positions)
    return simulate_events(positions, np.asarray(velocities, dtype=np.float64), gravity, np.broadcast_to(radii, n),
                           np.broadcast_to(masses, n), box, restitution, segments, frame_dt, n_frames, **options)


def rel(a, b):
    return abs(a - b) / abs(b)


def random_gas(n, size, radius, speed, seed):
    """n non-overlapping particles in (0, size)², random directions and speeds."""
    rng = np.random.default_rng(seed)
    positions = np.empty((0, 2))
    while len(positions) < n:
        candidate = rng.uniform(radius, size - radius, 2)
        if len(positions) == 0 or np.min(np.hypot(*(positions - candidate).T)) > 2 * radius:
            positions = np.vstack([positions, candidate])
    angle = rng.uniform(0, 2 * np.pi, n)
    velocities = speed * rng.uniform(0.5, 1.5, (n, 1)) * np.c_[np.cos(angle), np.sin(angle)]
    return positions, velocities, rng.uniform(0.5, 2.0, n)


def events_of(result, kind):
    keep = result.kind == kind
    return result.time[keep], result.i[keep], result.j[keep]


def test_event_times_match_closed_forms():
    # Two particles meet head on, then each goes to a wall; spectators at rest make
    # a grid of several cells, so the movers cross cells on the way.
    spectators = [(x, 37.0) for x in range(2, 40, 4)]
    result = run([(5.0, 20.0), (25.0, 20.0)] + spectators, [(3.0, 0.0), (-2.0, 0.0)] + [(0.0, 0.0)] * 10,
                 radii=[1.0, 1.5] + [0.5] * 10, box=(0.0, 0.0, 40.0, 40.0), frame_dt=0.5, n_frames=30)
    pair_times, pair_i, pair_j = events_of(result, 1)
    assert list(pair_i) == [0] and list(pair_j) == [1]
    assert rel(pair_times[0], 17.5 / 5.0) < 1e-12
    wall_times, wall_i, wall_j = events_of(result, 0)
    assert list(zip(wall_i, wall_j)) == [(1, 1), (0, 0)]   # equal masses exchange velocities
    assert rel(wall_times[1], 3.5 + 14.5 / 2.0) < 1e-12    # particle 0 from x = 15.5 to 1 at speed 2
    assert rel(wall_times[0], 3.5 + 20.5 / 3.0) < 1e-12    # particle 1 from x = 18 to 38.5 at speed 3


def test_bounce_times_under_gravity_match_closed_form():
    h, g = 6.0, 9.81
    result = run([(5.0, 1.0 + h)], [(0.0, 0.0)], gravity=(0.0, -g), box=(0.0, 0.0, 10.0, 20.0),
                 frame_dt=0.25, n_frames=16)
    fall = math.sqrt(2 * h / g)
    times, _, walls = events_of(result, 0)
    assert list(walls) == [2, 2]
    assert rel(times[0], fall) < 1e-12 and rel(times[1], 3 * fall) < 1e-12
    assert rel(result.impulse[0], 2 * g * fall) < 1e-12


def test_gas_conserves_energy_without_overlap_or_escape():
    size, radius = 60.0, 1.0
    positions, velocities, masses = random_gas(250, size, radius, 20.0, seed=7)
    result = run(positions, velocities, radii=radius, masses=masses, box=(0.0, 0.0, size, size),
                 frame_dt=1 / 60, n_frames=600)
    energy = 0.5 * (masses * (result.velocities ** 2).sum(-1)).sum(-1)
    assert np.abs(energy / energy[0] - 1).max() <= 1e-10
    assert result.pair_collisions.sum() > 5000 and result.wall_collisions.sum() > 500
    i, j = np.triu_indices(250, 1)
    for chunk in np.array_split(result.positions, 12):
        distance = np.hypot(*(chunk[:, i] - chunk[:, j]).transpose(2, 0, 1))
        assert distance.min() >= 2 * radius * (1 - 1e-9)
    assert result.positions.min() >= radius and result.positions.max() <= size - radius
    assert not result.budget_exceeded.any()


def test_momentum_is_conserved_by_pair_collisions():
    rng = np.random.default_rng(3)
    lattice = np.array([(3.0 * a, 3.0 * b) for a in range(-2, 2) for b in range(-1, 2)])
    positions = lattice + rng.uniform(-0.5, 0.5, (12, 2))
    velocities = -positions + rng.normal(0, 1, (12, 2))   # all heading for the middle
    masses = rng.uniform(0.5, 3.0, 12)
    result = run(positions, velocities, radii=0.8, masses=masses, box=(-1e3, -1e3, 1e3, 1e3), frame_dt=0.1,
                 n_frames=30)
    assert result.wall_collisions.sum() == 0 and result.pair_collisions.sum() >= 10
    momentum = (masses[:, None] * result.velocities).sum(1)
    scale = (masses[:, None] * np.abs(velocities)).sum()
    assert np.abs(momentum - momentum[0]).max() <= 1e-12 * scale


def test_newtons_cradle_passes_the_velocity_to_the_last_ball():
    positions = [(0.0, 0.0)] + [(3.0 + 2.0 * k, 0.0) for k in range(5)]
    velocities = [(1.0, 0.0)] + [(0.0, 0.0)] * 5
    result = run(positions, velocities, box=(-20.0, -20.0, 40.0, 20.0), frame_dt=0.5, n_frames=6)
    final = result.velocities[-1]
    assert np.abs(final[:5]).max() <= 1e-12
    assert np.abs(final[5] - [1.0, 0.0]).max() <= 1e-12
    assert result.pair_collisions.sum() == 5


def test_overlapping_pairs_collide_only_when_approaching():
    separating = run([(4.0, 5.0), (5.5, 5.0)], [(-1.0, 0.0), (1.0, 0.0)], n_frames=2)
    assert separating.pair_collisions.sum() == 0
    approaching = run([(4.0, 5.0), (5.5, 5.0)], [(1.0, 0.0), (-1.0, 0.0)], n_frames=2)
    times, _, _ = events_of(approaching, 1)
    assert list(times) == [0.0]
    assert np.abs(approaching.velocities[1] - [[-1.0, 0.0], [1.0, 0.0]]).max() <= 1e-15


@pytest.mark.parametrize("offset", [0.0, 0.8])
def test_simultaneous_mirrored_hits_stay_mirror_symmetric(offset):
    # Two particles hit a third from mirrored sides (y -> -y, and x -> -x when head on)
    # at the same instant: the outcome must be mirrored too.
    if offset == 0.0:
        positions, velocities = [(-3.0, 0.0), (0.0, 0.0), (3.0, 0.0)], [(1.0, 0.0), (0.0, 0.0), (-1.0, 0.0)]
        mirror = np.array([-1.0, 1.0])
    else:
        positions, velocities = [(-3.0, offset), (0.0, 0.0), (-3.0, -offset)], [(1.0, 0.0), (0.0, 0.0), (1.0, 0.0)]
        mirror = np.array([1.0, -1.0])
    result = run(positions, velocities, radii=0.5, box=(-50.0, -50.0, 50.0, 50.0), frame_dt=0.5, n_frames=8)
    assert result.pair_collisions.sum() == 2
    for sample in (result.positions, result.velocities):
        assert np.abs(sample[:, 0] * mirror - sample[:, 2]).max() <= 1e-12
        assert np.abs(sample[:, 1] * mirror - sample[:, 1]).max() <= 1e-12
    energy = (result.velocities ** 2).sum((1, 2))
    assert np.abs(energy / energy[0] - 1).max() <= 1e-12


def test_bouncing_ball_keeps_its_apex_height():
    g, apex = 100.0, 1.0
    result = run([(5.0, 1.0 + apex)], [(0.0, 0.0)], gravity=(0.0, -g), frame_dt=0.05, n_frames=600)
    assert result.wall_collisions.sum() >= 100
    height = result.positions[:, 0, 1] - 1.0 + result.velocities[:, 0, 1] ** 2 / (2 * g)
    assert np.abs(height / apex - 1).max() <= 1e-9


def test_very_fast_particle_stays_in_the_box():
    speed = 1e6
    result = run([(5.0, 5.0)], [(speed * math.cos(0.3), speed * math.sin(0.3))], radii=0.5, frame_dt=1 / 60,
                 n_frames=60)
    assert result.positions.min() >= 0.5 and result.positions.max() <= 9.5
    assert result.wall_collisions.sum() > 100_000
    assert np.abs(np.hypot(*result.velocities[-1, 0]) / speed - 1) < 1e-12


def test_fast_particles_never_cross_a_thin_segment():
    wall = np.array([[5.0, 0.0, 5.0, 10.0]])
    result = run([(2.0, 5.0), (8.0, 3.0)], [(1e5 * math.cos(0.7), 1e5 * math.sin(0.7)), (-3e4, 2e4)],
                 radii=[0.3, 0.2], gravity=(0.0, -9.81), segments=wall, frame_dt=1 / 60, n_frames=60)
    assert result.segment_collisions.sum() > 1000
    assert result.positions[:, 0, 0].max() <= 5.0 - 0.3 * (1 - 1e-9)
    assert result.positions[:, 1, 0].min() >= 5.0 + 0.2 * (1 - 1e-9)


def test_inelastic_bounces_end_resting_on_the_floor():
    result = run([(5.0, 8.0)], [(1.0, 0.0)], gravity=(0.0, -9.81), restitution=0.7, frame_dt=1 / 60, n_frames=600)
    assert result.positions[-1, 0, 1] == 1.0 and result.velocities[-1, 0, 1] == 0.0
    assert result.positions.min() >= 1.0 and result.positions.max() <= 9.0
    assert not result.budget_exceeded.any()


def test_ball_rests_on_a_ramp_slides_off_and_rests_on_the_floor():
    ramp = np.array([[1.0, 6.0, 7.0, 3.0]])
    result = run([(2.0, 8.0)], [(0.0, 0.0)], radii=0.5, gravity=(0.0, -9.81), restitution=0.5, segments=ramp,
                 frame_dt=1 / 60, n_frames=300)
    assert not result.budget_exceeded.any()
    assert result.segment_collisions.sum() >= 1
    assert result.positions[-1, 0, 1] == 0.5 and result.velocities[-1, 0, 1] == 0.0


def test_ball_dropped_on_a_resting_ball_stays_on_top():
    result = run([(5.0, 0.5), (5.0, 4.0)], np.zeros((2, 2)), radii=0.5, gravity=(0.0, -9.81), restitution=0.5,
                 frame_dt=1 / 60, n_frames=300)
    assert not result.budget_exceeded.any()
    assert result.positions[:, 1, 1].min() >= 1.5 * (1 - 1e-9)
    # Both settle, up to the invisible micro-bounce (a ten-thousandth of the radius).
    assert abs(result.positions[-1, 1, 1] - 1.5) <= 1e-4 and abs(result.positions[-1, 0, 1] - 0.5) <= 1e-4


def test_ball_comes_to_rest_wedged_at_the_bottom_of_a_v():
    vee = np.array([[1.0, 6.0, 5.0, 2.0], [5.0, 2.0, 9.0, 6.0]])
    result = run([(3.0, 8.0)], [(0.3, 0.0)], radii=0.5, gravity=(0.0, -9.81), restitution=0.5, segments=vee,
                 frame_dt=1 / 60, n_frames=600)
    assert not result.budget_exceeded.any()
    assert np.abs(result.positions[-1, 0] - [5.0, 2.0 + 0.5 * math.sqrt(2)]).max() <= 1e-12
    assert np.all(result.velocities[-1] == 0.0)


def test_budget_overrun_finishes_frames_safely():
    positions, velocities, masses = random_gas(100, 25.0, 1.0, 20.0, seed=5)
    result = run(positions, velocities, masses=masses, box=(0.0, 0.0, 25.0, 25.0), gravity=(0.0, -9.81),
                 restitution=0.5, frame_dt=1 / 60, n_frames=30, max_events_per_frame=30)
    assert result.budget_exceeded[1:].sum() >= 10 and not result.budget_exceeded[0]
    assert result.positions.min() >= 1.0 and result.positions.max() <= 24.0
    assert np.isfinite(result.velocities).all()
    # e = 0.5: the energy never grows, over budget or not
    energy = 0.5 * np.sum(masses * np.sum(result.velocities ** 2, axis=2), axis=1) + 9.81 * (
        result.positions[:, :, 1] @ masses)
    assert np.all(np.diff(energy) <= 1e-12 * energy[0])


def test_identical_inputs_give_identical_bytes():
    positions, velocities, masses = random_gas(60, 30.0, 0.8, 10.0, seed=11)
    segments = np.array([[10.0, 10.0, 20.0, 14.0], [5.0, 25.0, 5.0, 25.0]])
    first, second = (run(positions, velocities, radii=0.8, masses=masses, box=(0.0, 0.0, 30.0, 30.0),
                         gravity=(0.0, -3.0), restitution=0.9, segments=segments, frame_dt=1 / 30, n_frames=60,
                         max_events_per_frame=3000)
                     for _ in range(2))
    assert len(first.time) > 100
    for a, b in zip(first, second):
        assert a.dtype == b.dtype and a.tobytes() == b.tobytes()
