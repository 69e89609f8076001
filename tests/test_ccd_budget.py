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
