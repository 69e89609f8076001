"""Fast polygons under the discrete method: a polygon whose step reaches across the box keeps its
energy at the walls (its wall impacts met at their time of impact: engine/fast_polygons.py), a
polygon never passes a segment at any speed, and two polygons faster than the narrow phase can
follow are flagged approximate and announced once."""
import warnings

import numpy as np
import pytest

import collisim
from collisim.core.geometry.polygon import place_polygons
from collisim.shapes import box

FPS, SIZE = 30, 0.1


def run(world, seconds=1.0):
    """simulate() and the warnings it gave."""
    with warnings.catch_warnings(record=True) as said:
        warnings.simplefilter("always")
        traj = collisim.simulate(collisim.Scene(world=world, fps=FPS, seconds=seconds))
    return traj, [str(w.message) for w in said]


def kinetic_energy(world, traj):
    v, w = traj.velocities[:, 0], traj.angular_velocities[:, 0]
    return 0.5 * world.masses[0] * (v ** 2).sum(axis=1) + 0.5 * world.inertias[0] * w ** 2


def vertices_at(world, traj, frame):
    placed = np.empty_like(world.body_vertices)
    place_polygons(world.body_vertices, world.vertex_start, np.ascontiguousarray(traj.positions[frame], float),
                   np.ascontiguousarray(traj.angles[frame], float), placed)
    return placed


def folded(x, low, high):
    """Where free elastic flight along a line, unfolded to x, lies between two walls."""
    span = high - low
    phase = np.mod(x - low, 2 * span)
    return low + np.where(phase <= span, phase, 2 * span - phase)


@pytest.mark.parametrize("sizes_a_frame", [50, 200])
def test_a_fast_box_hitting_the_walls_flat_keeps_its_energy_and_its_path_and_does_not_turn(sizes_a_frame):
    # before: at 50 sizes a frame the box stopped dead at the wall (energy 1.0 lost) and turned
    speed = sizes_a_frame * SIZE * FPS
    world = collisim.World([[5.0, 5.0]], [[speed, 0.0]], polygons=[box(SIZE, SIZE)], box=(0, 0, 10, 10),
                           restitution=1.0)
    traj, _ = run(world)
    energy = kinetic_energy(world, traj)
    np.testing.assert_allclose(energy, energy[0], rtol=1e-6)
    assert np.abs(traj.angular_velocities).max() == 0.0 and np.abs(traj.angles).max() == 0.0
    # the closed form: the box's centre folded between x = 0.05 and 9.95
    t = np.arange(traj.frames + 1) / FPS
    np.testing.assert_allclose(traj.positions[:, 0, 0], folded(5.0 + speed * t, 0.05, 9.95), atol=1e-6)
    assert traj.wall_collisions.sum() >= 4


@pytest.mark.parametrize("sizes_a_frame", [50, 200])
def test_a_fast_tilted_box_keeps_its_energy_and_stays_in_the_box(sizes_a_frame):
    speed = sizes_a_frame * SIZE * FPS
    world = collisim.World([[5.0, 5.0]], [[speed, 0.37 * speed]], polygons=[box(SIZE, SIZE)], angles=0.3,
                           angular_velocities=2.0, box=(0, 0, 10, 10), restitution=1.0)
    traj, _ = run(world)
    energy = kinetic_energy(world, traj)
    np.testing.assert_allclose(energy, energy[0], rtol=1e-6)
    assert traj.wall_collisions.sum() >= 4
    for frame in range(traj.frames + 1):
        corners = vertices_at(world, traj, frame)
        assert corners.min() >= -1e-9 and corners.max() <= 10 + 1e-9


@pytest.mark.parametrize("restitution", [1.0, 0.0])
@pytest.mark.parametrize("sizes_a_frame", [30, 100, 1000])
def test_a_fast_polygon_never_passes_a_segment(sizes_a_frame, restitution):
    # before: from 30 sizes a frame the box ended frames below the segment
    speed = sizes_a_frame * SIZE * FPS
    world = collisim.World([[5.0, 8.0]], [[0.1 * speed, -speed]], polygons=[box(SIZE, SIZE)], angles=0.4,
                           box=(0, 0, 10, 10), restitution=restitution, segments=[[0.5, 5.0, 9.5, 5.0]])
    traj, _ = run(world, seconds=0.5)
    lowest = [vertices_at(world, traj, frame)[:, 1].min() for frame in range(traj.frames + 1)]
    assert min(lowest) >= 5.0 - 1e-9


def two_boxes(sizes_a_frame, apart=4.0):
    """Two boxes `apart` between centres flying at each other, each at sizes_a_frame sizes a frame."""
    speed = sizes_a_frame * SIZE * FPS
    return collisim.World([[5.0 - apart / 2, 5.0], [5.0 + apart / 2, 5.0]], [[speed, 0.0], [-speed, 0.0]],
                          polygons=[box(SIZE, SIZE), box(SIZE, SIZE)], box=(0, 0, 10, 10), restitution=1.0)


@pytest.mark.parametrize("sizes_a_frame", [2, 20])
def test_two_fast_polygons_do_not_pass_each_other_unflagged_and_the_run_says_so_once(sizes_a_frame):
    # before: at 2 sizes a frame each they passed through each other, no frame flagged
    traj, said = run(two_boxes(sizes_a_frame), seconds=0.5)
    swapped = np.flatnonzero(traj.positions[:, 0, 0] > traj.positions[:, 1, 0])
    if len(swapped):
        assert traj.approximate[:swapped[0] + 1].any()
    flagged = [line for line in said if "approximate" in line]
    assert (len(flagged) == 1) == traj.approximate.any()
    if flagged:
        assert "faster than" in flagged[0]


def test_two_slow_polygons_meet_exactly_and_are_not_flagged():
    traj, said = run(two_boxes(0.2, apart=1.0), seconds=1.0)
    assert not traj.approximate.any() and not said
    assert (traj.positions[:, 0, 0] < traj.positions[:, 1, 0]).all()
    np.testing.assert_allclose(traj.velocities[-1, :, 0], [-0.6, 0.6], rtol=1e-9)   # exchanged at e = 1
