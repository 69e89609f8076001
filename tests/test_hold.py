"""A heavy body on much lighter ones (response/hold.py): the contact solver's sweeps cannot carry
its weight down, so the rows left short are held from below, and the frames say so. Where the
sweeps converge, nothing is held and nothing is flagged."""
import warnings

import numpy as np
import pytest

import collisim
from collisim.analysis import metrics

G = (0.0, -9.8)


def stack(masses, fps=60, seconds=3.0, restitution=0.0, broadphase="auto"):
    """Balls of radius 0.5 touching in a column on the floor, the last on top; its run and warnings."""
    world = collisim.World([[10.0, 0.5 + k] for k in range(len(masses))], radii=0.5, masses=masses,
                           box=(0, 0, 20, 20), gravity=G, restitution=restitution)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        traj = collisim.simulate(collisim.Scene(world=world, fps=fps, seconds=seconds, broadphase=broadphase))
    return traj, [str(w.message) for w in caught]


@pytest.mark.parametrize("ratio, restitution", [(1e3, 0.0), (1e6, 0.5)])
def test_a_heavy_ball_rests_on_a_light_one(ratio, restitution):
    # without the hold the heavy ball sank through the light one: overlap 2 radii, both at y = 0.5
    traj, said = stack([1.0, ratio], restitution=restitution)
    assert metrics.max_overlap(traj) < 0.01
    assert traj.positions[-1, 1, 1] == pytest.approx(1.5, abs=0.005)
    assert traj.positions[-1, 0, 1] == pytest.approx(0.5, abs=1e-9)
    assert traj.approximate.any()
    flagged = [line for line in said if "approximate" in line]
    assert len(flagged) == 1 and "held those bodies from below, which does not keep momentum" in flagged[0]


def test_a_column_of_light_balls_carries_a_heavy_one():
    # the heavy ball's own row ends its sweeps met and every row below it late; it used to reach the floor
    traj, _ = stack([1.0] * 5 + [1e3], seconds=3.0)
    assert metrics.max_overlap(traj) < 0.1
    assert np.abs(traj.positions[:, :, 0] - 10.0).max() < 1e-9   # nothing is pushed sideways
    assert traj.positions[-1, -1, 1] == pytest.approx(5.5, abs=0.05)
    assert traj.approximate.any()


def test_the_held_run_is_the_same_whatever_the_broad_phase():
    a, _ = stack([1.0, 1.0, 1e3], seconds=1.0, broadphase="brute")
    b, _ = stack([1.0, 1.0, 1e3], seconds=1.0, broadphase="grid")
    assert a.approximate.any()
    np.testing.assert_array_equal(a.positions, b.positions)
    np.testing.assert_array_equal(a.approximate, b.approximate)


def test_nothing_is_held_where_the_sweeps_carry_the_weight():
    traj, said = stack([1.0, 10.0])   # a ratio the sweeps carry
    assert not traj.approximate.any() and not [line for line in said if "approximate" in line]
    assert metrics.max_overlap(traj) < 0.01
    # a pile of like masses whose sweeps stop short (friction) is left to them, as before
    pile = collisim.simulate(collisim.load_scene("polygons").replace(seconds=3.0))
    assert not pile.approximate.any()
    # nothing pulls: a heavy and a light ball pressed together in free space are never held
    world = collisim.World([[5.0, 5.0], [6.0, 5.0]], [[1.0, 0.0], [-1.0, 0.0]], radii=0.5, masses=[1e3, 1.0],
                           box=(0, 0, 20, 20), restitution=0.0)
    free = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=1.0))
    assert not free.approximate.any()
