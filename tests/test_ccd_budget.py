"""ccd over its event budget: frames whose last events are skipped, the state kept exact (fallback.py)."""
import numpy as np
import pytest

import collisim
from collisim.broadphase import find_pairs
from collisim.engine.ccd.events import simulate_events
from collisim.gas import lattice_gas


def energy(result, masses, gravity):
    """Kinetic + potential energy at every sample, potential -m g·p."""
    kinetic = 0.5 * np.sum(masses * np.sum(result.velocities ** 2, axis=2), axis=1)
    return kinetic - np.sum(masses * (result.positions @ np.asarray(gravity)), axis=1)


def worst_overlap(positions, radii):
    """The largest overlap over every sample, in radii of the smaller body."""
    worst = 0.0
    for p in positions:
        pairs = find_pairs("grid", p - radii[:, None], p + radii[:, None])
        d = np.hypot(*(p[pairs[:, 0]] - p[pairs[:, 1]]).T)
        worst = max(worst, np.max((radii[pairs].sum(axis=1) - d) / radii[pairs].min(axis=1), initial=0.0))
    return worst


@pytest.mark.parametrize("gravity", [(0.0, 0.0), (0.0, -9.8)])
def test_over_budget_frames_keep_the_energy_of_an_elastic_gas_and_leave_no_overlap(gravity):
    box = (0.0, 0.0, 32.0, 18.0)
    positions, velocities, radii = lattice_gas(300, box=box, speed=6.0, seed=4)
    masses = radii ** 2
    result = simulate_events(positions, velocities, gravity, radii, masses, box, 1.0, None, 1 / 60, 60,
                             max_events_per_frame=25)
    assert result.budget_exceeded[1:].sum() >= 50          # nearly every frame took the fallback
    e = energy(result, masses, gravity)
    assert np.abs(e / e[0] - 1).max() <= 1e-12
    assert worst_overlap(result.positions, radii) <= 1e-9
    low, high = np.array(box[:2]) + radii[:, None], np.array(box[2:]) - radii[:, None]
    assert np.all(result.positions >= low - 1e-12) and np.all(result.positions <= high + 1e-12)
    # not the exact run, but not frozen either: the speeds stay spread like a gas's
    assert np.std(np.hypot(*result.velocities[-1].T)) > 1.0


def test_a_single_fast_particle_over_budget_keeps_its_speed():
    result = simulate_events([[5.0, 5.0]], [[1e8 * np.cos(0.3), 1e8 * np.sin(0.3)]], (0.0, 0.0), [0.5], [1.0],
                             (0.0, 0.0, 10.0, 10.0), 1.0, None, 1 / 60, 30, max_events_per_frame=1000)
    assert result.budget_exceeded[1:].all()
    np.testing.assert_allclose(np.hypot(*result.velocities[:, 0].T), 1e8, rtol=1e-12)
    assert result.positions.min() >= 0.5 and result.positions.max() <= 9.5


def test_the_run_says_what_the_fallback_does(monkeypatch):
    from collisim import engine
    from collisim.engine.ccd import CCDStepper
    monkeypatch.setitem(engine.METHODS, "ccd", lambda s: CCDStepper(s.world, s.fps, s.frames, max_events_per_frame=3))
    scene = collisim.load_scene("particles_250").replace(method="ccd", seconds=0.25)
    with pytest.warns(UserWarning, match="energy exactly kept") as caught:
        traj = collisim.simulate(scene)
    assert len(caught) == 1 and "can lose energy" not in str(caught[0].message)
    ke = traj.kinetic_energy()
    assert traj.approximate.sum() > 0 and np.abs(ke / ke[0] - 1).max() <= 1e-12


def dropped_pile(restitution, seed, n=200, radius=0.5, columns=10):
    """benchmarks/ccd_settling.py's pile_world: n balls in loose rows, random velocities, dropped
    into a box `columns` diameters wide."""
    width = 2 * radius * columns
    rng = np.random.default_rng(seed)
    pitch = width / (columns - 1)
    x = (np.arange(n) % (columns - 1) + 0.5) * pitch + rng.uniform(-0.1, 0.1, n) * radius
    y = 3 * radius + (np.arange(n) // (columns - 1)) * 2.5 * radius
    return collisim.World(np.column_stack([x, y]), rng.normal(0, 0.5, (n, 2)), radius,
                          box=(0, 0, width, y.max() + 2 * radius), gravity=(0.0, -9.81), restitution=restitution)


@pytest.mark.slow
def test_a_storm_in_a_settling_pile_ends_and_the_pile_comes_to_rest():
    """200 balls dropped at e = 0.5 (seed 2 of the benchmark's piles), budget 20 000 events: at
    about 1 s a ball squeezed in a row on the floor, hit from above, rattles with its
    neighbours and fills the budget. Skipping the rest of such a frame held the bodies above up
    with it, and the storm came back every frame to the end (181 of 240 frames, the pile still
    moving at 4 s). Frozen where it is while the rest of the frame goes on (fallback.py), it
    ends: the pile comes to rest, exactly still over the last second, with no overlap."""
    w = dropped_pile(0.5, seed=2)
    result = simulate_events(w.positions, w.velocities, w.gravity, w.radii, w.masses, w.box, 0.5, None, 1 / 60,
                             240, max_events_per_frame=20_000)
    stormy = result.budget_exceeded
    assert 0 < stormy.sum() < 90                                   # the storm happens, and ends
    assert not stormy[-60:].any()
    assert np.all(result.velocities[-60:] == 0.0)                  # asleep, every body
    assert worst_overlap(result.positions, w.radii) <= 1e-9
