"""Convex polygon bodies in the World and the discrete engine: mass and inertia from the shape,
conservation in free space, a box's bounce, coming to rest with friction, a stack of boxes."""
import numpy as np
import pymunk
import pytest

import collisim
from collisim import Scene, World
from collisim.shapes import box, regular

G = 9.81


def run(world, seconds, fps=60):
    return collisim.simulate(Scene(world=world, fps=fps, seconds=seconds))


def total_energy(trajectory, world):
    return trajectory.kinetic_energy() + (world.masses * G * trajectory.positions[:, :, 1]).sum(-1)


def test_mass_and_inertia_come_from_the_shape():
    triangle = np.array([[0.0, 0.0], [2.0, 0.0], [0.5, 1.5]])
    world = World([(5, 5), (2, 2)], polygons=[triangle, None], radii=0.5, box=(0, 0, 10, 10))
    area = 1.5
    assert world.masses[0] == pytest.approx(area, rel=1e-12)
    assert world.masses[1] == pytest.approx(np.pi * 0.25, rel=1e-12)
    centroid = triangle.mean(axis=0)
    about_centroid = pymunk.moment_for_poly(area, (triangle - centroid).tolist())
    assert world.inertias[0] == pytest.approx(about_centroid, rel=1e-12)
    assert world.inertias[1] == pytest.approx(0.5 * world.masses[1] * 0.25, rel=1e-12)
    # the body's position becomes its centroid; the radius, its bounding circle's
    np.testing.assert_allclose(world.positions[0], np.array([5, 5]) + centroid, rtol=1e-15)
    assert world.radii[0] == pytest.approx(np.linalg.norm(triangle - centroid, axis=1).max(), rel=1e-15)


def test_a_clockwise_polygon_is_rewound_and_said_and_bad_ones_are_one_line():
    world = World([(5, 5)], polygons=[box(1, 1)[::-1]], box=(0, 0, 10, 10))
    assert world.notes and "clockwise" in world.notes[0]
    with pytest.raises(ValueError, match="not convex"):
        World([(5, 5)], polygons=[[[0, 0], [2, 0], [1, 0.2], [1, 2]]], box=(0, 0, 10, 10))
    with pytest.raises(ValueError, match="each of the 2 bodies"):
        World([(5, 5), (2, 2)], polygons=[box(1, 1)], box=(0, 0, 10, 10))
    overlapping = World([(5, 5), (5.9, 5)], polygons=[box(1, 1), box(1, 1)], box=(0, 0, 10, 10))
    with pytest.raises(ValueError, match="overlap"):   # refused where the engine starts
        collisim.simulate(Scene(world=overlapping))
    with pytest.raises(ValueError, match="ccd covers circles"):
        collisim.simulate(Scene(world=World([(5, 5)], polygons=[box(1, 1)], box=(0, 0, 10, 10)), method="ccd"))


def test_a_tilted_box_resting_on_the_floor_is_inside_the_box():
    # its bounding circle pokes through the floor; its corners do not
    World([(5, 0.5)], polygons=[box(1, 1)], box=(0, 0, 10, 10))


def test_contacts_of_two_boxes_face_to_face():
    world = World([(5, 5), (6.0, 5.2)], polygons=[box(1, 1), box(1, 1)], box=(0, 0, 10, 10))   # touching
    found = collisim.contacts(world, positions=[(5, 5), (5.95, 5.2)])
    assert found["pairs"].tolist() == [[0, 1], [0, 1]]
    np.testing.assert_allclose(found["normals"], [[1, 0], [1, 0]], atol=1e-15)
    np.testing.assert_allclose(found["depths"], [0.05, 0.05], rtol=1e-12)


@pytest.mark.parametrize("second", ["box", "circle", "pentagon"])
def test_collisions_in_free_space_keep_momentum_angular_momentum_and_energy(second):
    shape = {"box": box(1.2, 0.6), "circle": None, "pentagon": regular(5, 0.7)}[second]
    world = World([(45, 50), (50, 50.3)], velocities=[(3, 0.2), (-2, -0.1)], angular_velocities=[1.5, -2.0],
                  polygons=[box(1.0, 0.6), shape], radii=0.5, box=(0, 0, 100, 100), restitution=1.0)
    trajectory = run(world, 3.0)
    assert trajectory.pair_collisions.sum() >= 1
    m, inertia = world.masses, world.inertias
    p, v, w = trajectory.positions, trajectory.velocities, trajectory.angular_velocities
    momentum = (m[None, :, None] * v).sum(1)
    # about the fixed point (0, 0): orbital plus spin
    angular = (m * (p[:, :, 0] * v[:, :, 1] - p[:, :, 1] * v[:, :, 0])).sum(1) + (inertia * w).sum(1)
    kinetic = trajectory.kinetic_energy()
    assert np.abs(momentum - momentum[0]).max() <= 1e-10 * np.abs(momentum[0]).max()
    assert np.abs(angular - angular[0]).max() <= 1e-10 * abs(angular[0])
    assert np.abs(kinetic - kinetic[0]).max() <= 1e-10 * kinetic[0]


def test_a_box_dropped_flat_keeps_its_bounce_height_over_20_bounces():
    world = World([(5, 3.0)], polygons=[box(1.0, 0.5)], box=(0, 0, 10, 10), gravity=(0, -G), restitution=1.0)
    trajectory = run(world, 32.0)
    y = trajectory.positions[:, 0, 1]
    peaks = [y[k] for k in range(1, len(y) - 1) if y[k] >= y[k - 1] and y[k] > y[k + 1]]
    assert len(peaks) >= 20
    assert np.abs(np.array(peaks[:20]) - 3.0).max() < 0.01 * (3.0 - 0.25)
    assert np.abs(trajectory.angles).max() == 0.0      # a flat landing gives no spin


def test_a_tilted_box_with_friction_comes_to_rest_without_jitter():
    world = World([(5, 3.0)], polygons=[box(1.0, 0.5)], angles=0.4, box=(0, 0, 10, 10), gravity=(0, -G),
                  restitution=0.0, friction=0.5)
    trajectory = run(world, 4.0)
    drop_speed = np.sqrt(2 * G * (3.0 - 0.25))
    after = slice(3 * 60, None)
    assert np.hypot(*trajectory.velocities[after, 0].T).max() < 1e-3 * drop_speed
    assert np.abs(trajectory.angular_velocities[after, 0]).max() * 0.56 < 1e-3 * drop_speed
    # on a face: centre half the height above the floor
    assert trajectory.positions[-1, 0, 1] == pytest.approx(0.25, abs=0.01 * 0.5)


@pytest.mark.slow
def test_a_stack_of_six_boxes_stands_for_30_seconds():
    h = 0.5
    world = World([(5, h / 2 + h * k) for k in range(6)], polygons=[box(1.0, h)] * 6, box=(0, 0, 10, 10),
                  gravity=(0, -G), restitution=0.0, friction=0.5)
    trajectory = run(world, 30.0)
    assert np.abs(trajectory.positions[:, :, 0] - 5.0).max() < 0.01 * 1.0
    assert np.abs(trajectory.positions[:, :, 1] - world.positions[:, 1]).max() < 0.01 * 1.0
    gaps = np.diff(trajectory.positions[:, :, 1], axis=1)
    assert (h - gaps).max() < 0.01 * h                     # no overlap above 1 % of size
    energy = total_energy(trajectory, world)
    assert energy.max() <= energy[0] * (1 + 1e-12) + 1e-12


@pytest.mark.parametrize("seed", [0, 4])
def test_a_column_of_sixteen_slightly_tilted_boxes_stands(seed):
    """Each box on the one below touches at one corner and is raised at the other: both ends are
    held (a speculative point at the raised one), so the column does not walk apart, and what
    rocking the solver leaves stays below the rest speed (sleeping, which never freezes a body
    its contacts still move, need not catch it)."""
    rng = np.random.default_rng(seed)
    h, n = 0.5, 16
    positions = [(5.0 + rng.uniform(-0.05, 0.05), 0.01 + h / 2 + k * (h * 1.001 + 0.01)) for k in range(n)]
    world = World(positions, polygons=[box(1.0, h)] * n, angles=rng.uniform(-0.01, 0.01, n), box=(0, 0, 10, 12),
                  gravity=(0, -G), restitution=0.0, friction=0.5)
    trajectory = run(world, 5.0)
    spread = np.ptp(trajectory.positions[-1, :, 0]) - np.ptp(trajectory.positions[0, :, 0])
    assert spread < 0.06 * 1.0                        # it stood (the columns that walked apart: 0.07-0.25)
    rest_speed = np.sqrt(2 * G * 1e-3 * np.hypot(0.5, h / 2))   # engine/rest.py's, for these boxes
    assert np.abs(trajectory.velocities[-60:]).max() < rest_speed


def test_a_trajectory_file_keeps_the_polygons(tmp_path):
    world = World([(3, 3), (6, 3)], polygons=[regular(5, 0.6), None], radii=0.4, angles=[0.3, 0.0], friction=0.25,
                  box=(0, 0, 10, 10), gravity=(0, -G))
    trajectory = run(world, 0.5)
    trajectory.save(tmp_path / "run.npz")
    loaded = collisim.load_trajectory(tmp_path / "run.npz")
    assert loaded.world.shapes.tolist() == world.shapes.tolist() and loaded.world.friction == 0.25
    np.testing.assert_array_equal(loaded.world.body_vertices, world.body_vertices)
    np.testing.assert_array_equal(loaded.world.positions, world.positions)
    np.testing.assert_array_equal(loaded.angles, trajectory.angles)
