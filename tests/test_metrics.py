"""collisim.analysis.metrics on trajectories built by hand, where every answer is known."""
import numpy as np
import pytest
from scipy import stats

import collisim
from collisim.analysis import metrics
from collisim.core.kinds import PAIR, SEGMENT, WALL
from collisim.model.trajectory import Events, Trajectory
from collisim.model.world import World

FPS = 10.0


def trajectory(positions, velocities=None, radii=0.5, masses=1.0, events=None):
    """A Trajectory sampled at FPS from positions (F, n, 2), in a box large enough for them."""
    positions = np.asarray(positions, float)
    frames, n = positions.shape[:2]
    zeros = np.zeros(frames, np.int64)
    spread = np.column_stack([10.0 * np.arange(n), np.zeros(n)])   # the World only needs a valid start
    world = World(spread, radii=np.broadcast_to(np.asarray(radii, float), (n,)),
                  masses=np.broadcast_to(np.asarray(masses, float), (n,)), box=(-1e6, -1e6, 1e6, 1e6))
    return Trajectory(times=np.arange(frames) / FPS, positions=positions,
                      velocities=np.zeros_like(positions) if velocities is None else np.asarray(velocities, float),
                      angles=np.zeros((frames, n)), angular_velocities=np.zeros((frames, n)),
                      wall_collisions=zeros, pair_collisions=zeros, segment_collisions=zeros, candidates=zeros,
                      approximate=np.zeros(frames, bool),
                      world=world, fps=FPS, events=events or Events.empty())


def events(*rows):
    """Events from (time, kind, i, j, impulse) rows."""
    t, kind, i, j, impulse = (np.array(c) for c in zip(*rows))
    return Events(t.astype(float), kind.astype(np.int8), i.astype(np.intp), j.astype(np.intp),
                  impulse.astype(float), np.zeros((len(rows), 2)))


def straight(start, velocity, frames):
    """(frames, 2) positions of a particle moving at constant velocity, sampled at FPS."""
    return np.asarray(start, float) + np.outer(np.arange(frames) / FPS, velocity)


# --- energy and momentum -------------------------------------------------------------------------

def test_free_fall_sampled_exactly_has_no_energy_drift():
    world = collisim.World([[5.0, 8.0]], [[1.0, 0.0]], radii=0.5, masses=2.0, gravity=(0, -9.8))
    t = np.arange(11) / FPS
    positions = np.column_stack([5.0 + t, 8.0 - 4.9 * t ** 2])[:, None, :]
    velocities = np.column_stack([np.ones_like(t), -9.8 * t])[:, None, :]
    traj = trajectory(positions, velocities, radii=0.5, masses=2.0)
    assert metrics.energy_drift(traj, world) < 1e-12
    # measured from the floor (y = ymin + r): U = m g (8 - 0.5) at the start
    assert metrics.potential_energy(traj, world)[0] == pytest.approx(2 * 9.8 * 7.5)


def test_energy_drift_is_relative_to_the_starting_energy():
    world = collisim.World([[5.0, 5.0]], [[2.0, 0.0]], masses=1.0)
    velocities = np.array([[[2.0, 0.0]], [[2.0, 0.0]], [[0.0, 2.2]]])
    traj = trajectory(np.full((3, 1, 2), 5.0), velocities)
    assert metrics.energy_drift(traj, world) == pytest.approx(0.21)       # E: 2 -> 2.42


def test_momentum_drift():
    velocities = np.array([[[1.0, 0.0], [-1.0, 0.0]], [[1.0, 0.0], [0.0, 0.0]]])
    traj = trajectory(np.zeros((2, 2, 2)), velocities, masses=[1.0, 3.0])
    # P: (-2, 0) -> (1, 0); Σ m|v0| = 4
    assert metrics.momentum_drift(traj) == pytest.approx(3 / 4)


# --- geometry ------------------------------------------------------------------------------------

def test_max_overlap_in_radii_of_the_smaller_circle():
    positions = np.array([[[0.0, 0.0], [2.0, 0.0]], [[0.0, 0.0], [1.3, 0.0]], [[0.0, 0.0], [1.6, 0.0]]])
    traj = trajectory(positions, radii=[0.5, 1.0])
    np.testing.assert_allclose(metrics.overlaps(traj), [0.0, 0.4, 0.0], atol=1e-12)
    assert metrics.max_overlap(traj) == pytest.approx(0.4)


def test_max_overlap_matches_brute_force(rng):
    positions = rng.uniform(0, 10, (5, 60, 2))
    radii = rng.uniform(0.2, 0.8, 60)
    traj = trajectory(positions, radii=radii)
    i, j = np.triu_indices(60, 1)
    distance = np.linalg.norm(positions[:, j] - positions[:, i], axis=2)
    brute = ((radii[i] + radii[j] - distance) / np.minimum(radii[i], radii[j])).max()
    assert metrics.max_overlap(traj) == pytest.approx(max(brute, 0.0))


def test_outside_counts_centres_out_of_the_box():
    world = collisim.World([[2.0, 5.0], [5.0, 5.0], [8.0, 5.0]], radii=0.5)      # box 0..10
    positions = np.array([[[5, 5], [5, 5], [5, 5]],
                          [[-0.2, 5], [9.8, 5], [5, 5]],     # first escaped, second only grazes
                          [[5, 5], [9.8, 5], [5, 10.3]]], float)
    traj = trajectory(positions)
    assert metrics.outside(traj, world) == (1, 2)
    assert metrics.outside(traj, world, depth=0.0) == (2, 3)   # any part of a circle beyond a wall


# --- tunnelling ----------------------------------------------------------------------------------

def head_on(gap_before, gap_after, offset=0.0, frames=2):
    """Two circles of radius 0.5 along x, gap = x_right - x_left, at two samples; the right one
    is `offset` above the left one."""
    left = np.zeros((frames, 2))
    right = np.column_stack([np.linspace(gap_before, gap_after, frames), np.full(frames, offset)])
    return np.stack([left, right], axis=1)


def test_pass_through_between_samples_is_missed():
    traj = trajectory(head_on(1.5, -1.5))
    np.testing.assert_array_equal(metrics.missed_collisions(traj), [0, 1])


def test_pass_through_that_ends_overlapping_is_missed():
    # the centres crossed and the circles still overlap at the second sample
    assert metrics.missed_collisions(trajectory(head_on(1.5, -0.5))).sum() == 1


def test_grazing_between_samples_is_missed():
    # closest approach 0.9 < 1.0 half way, apart at both samples
    assert metrics.missed_collisions(trajectory(head_on(3.0, -3.0, offset=0.9))).sum() == 1
    assert metrics.missed_collisions(trajectory(head_on(3.0, -3.0, offset=1.1))).sum() == 0


def test_approach_into_an_overlap_found_at_the_sample_is_not_missed():
    assert metrics.missed_collisions(trajectory(head_on(1.5, 0.8))).sum() == 0


def test_registered_collision_is_not_missed():
    hit = events((0.05, PAIR, 0, 1, 1.0))
    assert metrics.missed_collisions(trajectory(head_on(1.5, -1.5), events=hit)).sum() == 0
    # a collision with a wall bends the path: the pair is not judged in that frame
    wall = events((0.1, WALL, 1, 0, 1.0))
    assert metrics.missed_collisions(trajectory(head_on(1.5, -1.5), events=wall)).sum() == 0
    # a collision in the frame before does not excuse this one
    positions = np.concatenate([head_on(3.0, 3.0)[:1], head_on(1.5, -1.5)])   # gaps 3, 1.5, -1.5
    earlier = events((0.1, PAIR, 0, 1, 1.0))
    np.testing.assert_array_equal(metrics.missed_collisions(trajectory(positions, events=earlier)), [0, 0, 1])


def test_event_at_a_frame_time_belongs_to_the_interval_it_ends():
    # discrete steps stamp k·dt, which may exceed f/fps in the last bit
    step_end = np.nextafter(0.3, 1.0)
    ev = events((step_end, PAIR, 0, 1, 1.0), (0.3 + 1e-3 / FPS, WALL, 0, 0, 1.0), (0.05, WALL, 0, 0, 1.0))
    traj = trajectory(np.zeros((5, 2, 2)), events=ev)
    np.testing.assert_array_equal(metrics.event_frames(traj), [3, 4, 1])


def barrier_world():
    return collisim.World([[4.0, 5.0], [1.0, 1.0]], radii=0.2, segments=[[5.0, 2.0, 5.0, 8.0]])


def test_barrier_crossing_within_the_segment():
    positions = np.array([[[4.0, 5.0], [1.0, 1.0]], [[6.0, 5.0], [1.0, 1.0]], [[6.5, 5.0], [1.0, 1.0]]])
    traj = trajectory(positions)
    np.testing.assert_array_equal(metrics.missed_segment_crossings(traj, barrier_world()), [0, 1, 0])


def test_barrier_crossing_beside_the_segment_or_bouncing_back_is_not_counted():
    beside = np.array([[[4.0, 9.0], [1.0, 1.0]], [[6.0, 9.0], [1.0, 1.0]]])      # y = 9 is past its end
    bounced = np.array([[[4.0, 5.0], [1.0, 1.0]], [[4.5, 5.0], [1.0, 1.0]]])
    diagonal = np.array([[[4.0, 1.0], [1.0, 1.0]], [[6.0, 3.0], [1.0, 1.0]]])    # meets x = 5 at y = 2
    world = barrier_world()
    assert metrics.missed_segment_crossings(trajectory(beside), world).sum() == 0
    assert metrics.missed_segment_crossings(trajectory(bounced), world).sum() == 0
    assert metrics.missed_segment_crossings(trajectory(diagonal), world).sum() == 1   # end point counts


# --- walls ---------------------------------------------------------------------------------------

def test_wall_pressure_is_impulse_per_time_and_length():
    world = collisim.World([[2.0, 0.5]], radii=0.5, box=(0, 0, 4, 1))           # perimeter 10
    ev = events((0.1, WALL, 0, 0, 2.0), (0.2, WALL, 0, 1, 3.0), (0.2, PAIR, 0, 1, 50.0),
                (0.3, SEGMENT, 0, 0, 70.0))
    traj = trajectory(np.full((11, 1, 2), 0.5), events=ev)                   # 1 s long
    assert metrics.wall_pressure(traj, world) == pytest.approx(5.0 / (1.0 * 10.0))


# --- agreement between runs ----------------------------------------------------------------------

def test_position_error_in_radii_at_the_nearest_frame():
    base = np.zeros((11, 2, 2))
    shifted = base.copy()
    shifted[5:, 0, 0] += 1.0                   # from 0.5 s on, particle 0 is one unit off
    a, b = trajectory(shifted, radii=[0.5, 1.0]), trajectory(base, radii=[0.5, 1.0])
    assert metrics.position_error(a, b, 0.42) == 0.0            # nearest frame 0.4 s
    assert metrics.position_error(a, b, 0.48) == pytest.approx(np.sqrt((2.0 ** 2 + 0) / 2))


def test_two_sample_ks_matches_scipy(rng):
    a, b = rng.rayleigh(1.0, 300), rng.rayleigh(1.1, 500)
    assert metrics.speed_distribution_ks(a, b) == pytest.approx(stats.ks_2samp(a, b).statistic)
    assert metrics.speed_distribution_ks(a, a) == 0.0


def test_one_sample_ks_matches_scipy(rng):
    x = rng.rayleigh(1.0, 400)
    cdf = stats.rayleigh(scale=1.0).cdf
    assert metrics.ks_statistic(x, cdf) == pytest.approx(stats.kstest(x, cdf).statistic)


def test_maxwell_boltzmann_for_equal_masses_is_rayleigh():
    v = np.linspace(0, 6, 50)
    mass, mean_energy = 2.0, 1.5                      # kT = 1.5: sigma^2 = kT / m
    expected = stats.rayleigh(scale=np.sqrt(mean_energy / mass)).cdf(v)
    np.testing.assert_allclose(metrics.maxwell_boltzmann_cdf(v, mean_energy, np.full(7, mass)), expected)


def test_maxwell_boltzmann_mixture_fits_equipartitioned_samples(rng):
    masses = np.repeat([1.0, 4.0], [3000, 1000])
    kT = 0.8
    speeds = rng.rayleigh(np.sqrt(kT / masses))
    assert np.mean(0.5 * masses * speeds ** 2) == pytest.approx(kT, rel=0.05)   # 2D: kT per particle
    law = lambda s: metrics.maxwell_boltzmann_cdf(s, kT, masses)  # noqa: E731
    assert metrics.ks_statistic(speeds, law) < 1.63 / np.sqrt(len(speeds))       # 99 % level
    wrong = lambda s: metrics.maxwell_boltzmann_cdf(s, kT, np.ones_like(masses))  # noqa: E731
    assert metrics.ks_statistic(speeds, wrong) > 0.1


def test_sampled_speeds_picks_frames_from_a_time_on():
    velocities = np.arange(11, dtype=float)[:, None, None] * np.array([[[3.0, 4.0]]])
    traj = trajectory(np.zeros((11, 1, 2)), velocities)
    np.testing.assert_allclose(metrics.sampled_speeds(traj, 0.5, 0.2), [25.0, 35.0, 45.0])


def test_overlaps_with_polygons_are_the_deepest_contact_over_the_smaller_radius():
    """Two unit squares overlapping by 0.1 along x, turned a quarter turn (the same squares), and
    a circle of radius 0.5 reaching 0.25 into the second one's far face: closed forms for each
    frame, in radii of the smaller body (a square's bounding radius is √½)."""
    from collisim.shapes import box as square
    half_diagonal = np.sqrt(0.5)
    world = World([[0.0, 0.0], [5.0, 0.0], [10.0, 0.0]], radii=[1.0, 1.0, 0.5],
                  polygons=[square(1, 1), square(1, 1), None], box=(-100, -100, 100, 100))
    positions = np.array([[[0.0, 0.0], [0.9, 0.0], [5.0, 0.0]],          # squares 0.1 deep
                          [[0.0, 0.0], [0.9, 0.0], [1.65, 0.0]],         # and the circle 0.25 into square 1
                          [[0.0, 0.0], [3.0, 0.0], [6.0, 0.0]]])         # nothing touches
    angles = np.array([[0.0, 0.0, 0.0], [np.pi / 2, 0.0, 0.0], [0.0, 0.0, 0.0]])
    zeros = np.zeros(3, np.int64)
    traj = Trajectory(times=np.arange(3) / FPS, positions=positions, velocities=np.zeros_like(positions),
                      angles=angles, angular_velocities=np.zeros((3, 3)), wall_collisions=zeros,
                      pair_collisions=zeros, segment_collisions=zeros, candidates=zeros,
                      approximate=np.zeros(3, bool), world=world, fps=FPS, events=Events.empty())
    expected = [0.1 / half_diagonal, 0.25 / 0.5, 0.0]
    np.testing.assert_allclose(metrics.overlaps(traj), expected, rtol=1e-9, atol=1e-12)
    assert metrics.max_overlap(traj) == pytest.approx(0.5, rel=1e-9)
