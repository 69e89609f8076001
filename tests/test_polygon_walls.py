"""A polygon meets the box walls at any speed and size: it never passes one, it comes to rest on
the floor, and an elastic bounce keeps its energy (rows.wall_manifolds' reach)."""
import numpy as np
import pytest

import collisim
from collisim.analysis import metrics
from collisim.shapes import box

G, FPS = 9.8, 30


def dropped(size, restitution, seconds=3.0):
    """A square of side `size` let go at y = 5 in a 10 x 10 box: it meets the floor at 9.8 units/s,
    0.33 units a frame, from 30 to 33 000 000 times its size a frame."""
    world = collisim.World([[5.0, 5.0]], polygons=[box(size, size)], box=(0, 0, 10, 10), gravity=(0.0, -G),
                           restitution=restitution)
    return world, collisim.simulate(collisim.Scene(world=world, fps=FPS, seconds=seconds))


@pytest.mark.parametrize("size", [1e-6, 0.01, 0.3])
def test_a_fast_small_polygon_lands_on_the_floor_and_stays_in_the_box(size):
    # before: a box of 0.01 went 0.23 through the floor and came to rest below it (its margin,
    # capped at its size, never reached the floor)
    world, traj = dropped(size, 0.0)
    y = traj.positions[:, 0, 1]
    assert metrics.outside(traj, world) == (0, 0)
    assert y.min() >= size / 2 * (1 - 0.01)
    assert y[-1] == pytest.approx(size / 2, rel=1e-3)
    assert np.abs(traj.velocities[-1]).max() < 1e-6


@pytest.mark.parametrize("size", [1e-6, 0.01, 0.3])
def test_an_elastic_polygon_keeps_its_energy_and_stays_in_the_box(size):
    world, traj = dropped(size, 1.0)
    y, vy = traj.positions[:, 0, 1], traj.velocities[:, 0, 1]
    np.testing.assert_allclose(y + vy ** 2 / (2 * G), 5.0, rtol=1e-12)   # its energy, at every frame
    assert y.min() >= size / 2 * (1 - 0.01) and metrics.outside(traj, world) == (0, 0)
