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


@pytest.mark.parametrize("size", [1e-6, 0.01, 0.3, 1.0])
def test_an_inelastic_polygon_lands_where_its_fall_meets_the_floor_without_hovering(size):
    # before: a box of 0.3 stopped 0.26 above the floor, where the step that met it began, and
    # sank the rest over six frames (an impact at the step's start, with e = 0)
    world, traj = dropped(size, 0.0, seconds=1.5)
    t = np.arange(len(traj.positions)) / FPS
    fall = 5.0 - 0.5 * G * t ** 2          # free fall is exact in the discrete step
    rest = size / 2
    y = traj.positions[:, 0, 1]
    landed = fall <= rest
    np.testing.assert_allclose(y[~landed], fall[~landed], rtol=1e-12)
    np.testing.assert_allclose(y[landed], rest, rtol=1e-9, atol=1e-12)
    assert np.abs(traj.velocities[landed]).max() < 1e-4   # (the rest pass's few sweeps)
    walls = traj.events.kind == collisim.core.kinds.WALL
    first = np.argmax(landed)
    np.testing.assert_allclose(traj.events.time[walls], first / FPS, rtol=1e-12)
    assert walls.sum() == 2   # its face's two corners, once


def test_an_inelastic_polygon_lands_on_a_segment_where_its_fall_meets_it():
    # a slower fall (0.05 a frame at 60 fps): a segment's rows reach as far as the body's margin
    world = collisim.World([[5.0, 3.0]], polygons=[box(0.3, 0.3)], box=(0, 0, 10, 10), gravity=(0.0, -G),
                           restitution=0.0, segments=[[1.0, 2.0, 9.0, 2.0]])
    traj = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=1.0))
    t = np.arange(len(traj.positions)) / 60
    fall = 3.0 - 0.5 * G * t ** 2
    y = traj.positions[:, 0, 1]
    landed = fall <= 2.15
    np.testing.assert_allclose(y[~landed], fall[~landed], rtol=1e-12)
    np.testing.assert_allclose(y[landed], 2.15, rtol=1e-9)
