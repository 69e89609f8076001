"""World(damping=d): a body keeps the fraction d of its velocity over a second of free motion, as
pymunk's Space.damping; the discrete method applies d**dt every step, ccd refuses it in one line."""
import numpy as np
import pytest

import collisim
from collisim.analysis.reference.plain_pymunk import simulate_plain_pymunk

FPS = 60


def free_scene(damping, gravity=(0.0, 0.0), angular=0.0, seconds=1.0):
    world = collisim.World([[5.0, 500.0]], [[3.0, -2.0]], radii=0.5, box=(0, 0, 1000, 1000), gravity=gravity,
                           angular_velocities=angular, damping=damping)
    return collisim.Scene(world=world, fps=FPS, seconds=seconds, broadphase="brute")


@pytest.mark.parametrize("damping", [0.0, 0.25, 0.9, 1.0])
def test_a_free_body_keeps_the_fraction_d_of_its_velocity_each_second(damping):
    run = collisim.simulate(free_scene(damping, angular=4.0, seconds=2.0))
    keep = damping ** (1 / FPS)
    steps = np.arange(len(run.times))
    expected_v = np.array([3.0, -2.0]) * keep ** steps[:, None]
    np.testing.assert_allclose(run.velocities[:, 0], expected_v, rtol=1e-12, atol=1e-300)
    np.testing.assert_allclose(run.velocities[FPS, 0], [3.0 * damping, -2.0 * damping], rtol=1e-12, atol=1e-300)
    # each step moves by its damped velocity: x_k = x_0 + dt * sum_{j <= k} v_0 keep^j
    travelled = np.cumsum(np.where(steps > 0, keep ** steps, 0.0)) / FPS
    np.testing.assert_allclose(run.positions[:, 0], [5.0, 500.0] + travelled[:, None] * [3.0, -2.0], rtol=1e-12)


def test_damping_slows_turning_alike():
    run = collisim.simulate(free_scene(0.5, angular=4.0, seconds=1.0))
    np.testing.assert_allclose(run.angular_velocities[-1, 0], 2.0, rtol=1e-12)


def test_a_damped_fall_matches_pymunk_velocity_for_velocity():
    """pymunk updates v <- v * d**dt + g dt, as the discrete step does (its positions differ:
    pymunk's step is semi-implicit, collisim's exact for constant acceleration)."""
    scene = free_scene(0.6, gravity=(0.0, -9.8), seconds=1.5)
    ours, theirs = collisim.simulate(scene), simulate_plain_pymunk(scene)
    np.testing.assert_allclose(ours.velocities, theirs.velocities, rtol=1e-9, atol=1e-12)
    # v_N = v0 k^N - g dt (1 - k^N) / (1 - k), k = d**dt: a fall tends to g dt / (1 - k), not on for ever
    keep, steps = 0.6 ** (1 / FPS), np.arange(len(ours.times))
    np.testing.assert_allclose(ours.velocities[:, 0, 1], -2.0 * keep ** steps - 9.8 / FPS * (1 - keep ** steps) / (1 - keep),
                               rtol=1e-12)


def test_damped_balls_in_a_box_come_to_a_stop_and_lose_energy_monotonically():
    rng = np.random.default_rng(3)
    positions = np.column_stack([np.repeat(np.arange(1.0, 10.0, 2.0), 5), np.tile(np.arange(1.0, 10.0, 2.0), 5)])
    world = collisim.World(positions, rng.normal(0.0, 4.0, (25, 2)), radii=0.4, damping=0.3)
    run = collisim.simulate(collisim.Scene(world=world, fps=FPS, seconds=6.0))
    energy = 0.5 * (world.masses[None, :, None] * run.velocities ** 2).sum(axis=(1, 2))
    assert np.all(np.diff(energy) <= 1e-12 * energy[0])   # elastic contacts, damped flight: never gains
    assert energy[-1] < 1e-6 * energy[0]


def test_damping_is_kept_in_a_saved_trajectory(tmp_path):
    run = collisim.simulate(free_scene(0.5, seconds=0.1))
    again = collisim.load_trajectory(run.save(tmp_path / "run.npz"))
    assert again.world.damping == 0.5


@pytest.mark.parametrize("value, words", [(1.5, r"damping must be in \[0, 1\], got 1.5"),
                                          (-0.1, r"damping must be in \[0, 1\]"),
                                          ("0.5", "damping must be a number")])
def test_a_bad_damping_is_one_line(value, words):
    with pytest.raises(ValueError, match=words):
        collisim.World([[1.0, 1.0]], damping=value)


def test_ccd_refuses_damping_in_one_line_and_the_command_writes_nothing(tmp_path):
    scene = free_scene(0.5).replace(method="ccd")
    with pytest.raises(ValueError, match="ccd .* does not model damping .*use method discrete"):
        collisim.simulate(scene)
    with pytest.raises(ValueError, match="does not model damping"):
        collisim.render(scene, tmp_path / "out.mp4")
    assert list(tmp_path.iterdir()) == []
