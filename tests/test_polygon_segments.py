"""Polygons on segments: the manifold against shapely, a box sliding down an incline (closed form,
with and without friction), a box bouncing on a shelf, the events a segment gives."""
import numpy as np
import pytest
import shapely.geometry as sg

import collisim
from collisim import Scene, World
from collisim.core.geometry.polygon import place_polygons
from collisim.core.kinds import N_WALLS, SEGMENT
from collisim.narrowphase.manifold import polygon_segment_manifold
from collisim.shapes import box, regular

G = 9.81


def run(world, seconds, fps=60):
    return collisim.simulate(Scene(world=world, fps=fps, seconds=seconds))


def test_the_manifold_agrees_with_shapely_on_random_polygons_and_segments():
    rng = np.random.default_rng(7)
    agreed = 0
    for _ in range(2000):
        shape = regular(int(rng.integers(3, 8)), rng.uniform(0.3, 1.5)) if rng.random() < 0.6 else \
            box(rng.uniform(0.2, 2), rng.uniform(0.2, 2))
        world = World([(0.0, 0.0)], polygons=[shape], angles=rng.uniform(0, 2 * np.pi), box=(-10, -10, 10, 10))
        vertices = np.empty_like(world.body_vertices)
        place_polygons(world.body_vertices, world.vertex_start, world.positions, world.angles, vertices)
        centre, half = rng.uniform(-2, 2, 2), rng.uniform(0, 2) * np.array([np.cos(a := rng.uniform(0, np.pi)),
                                                                           np.sin(a)])
        segment = np.array([[*(centre - half), *(centre + half)]])
        m = polygon_segment_manifold(vertices, world.vertex_start, 0, segment, 0, 0.0)
        polygon, line = sg.Polygon(vertices), sg.LineString(segment[0].reshape(2, 2))
        if polygon.buffer(1e-9).intersects(line) != polygon.buffer(-1e-9).intersects(line):
            continue   # touching within rounding: either answer is right
        assert (m[2] > 0) == polygon.intersects(line)
        if m[2] > 0:
            assert np.hypot(m[0], m[1]) == pytest.approx(1.0, abs=1e-12)
            for k in range(m[2]):   # each point lies within its depth of the polygon and of the segment
                depth, point = m[3 + 3 * k], sg.Point(m[4 + 3 * k], m[5 + 3 * k])
                assert depth >= 0.0
                assert point.distance(polygon) <= depth + 1e-9 and point.distance(line) <= depth + 1e-9
        agreed += 1
    assert agreed > 1900


def incline(theta, length=20.0):
    """A segment through (1, 1) rising at theta, and the point at distance s along it."""
    direction = np.array([np.cos(theta), np.sin(theta)])
    start = np.array([1.0, 1.0])
    return np.array([[*start, *(start + length * direction)]]), start, direction


@pytest.mark.parametrize("friction", [0.0, 0.2, 0.8])
def test_a_box_on_an_incline_slides_as_the_closed_form_says(friction):
    theta = np.radians(30)
    segment, start, along = incline(theta)
    normal = np.array([-np.sin(theta), np.cos(theta)])
    centre = start + 12.0 * along + 0.25 * normal           # a 1 x 0.5 box resting on its long face
    world = World([centre], polygons=[box(1.0, 0.5)], angles=theta, segments=segment, box=(0, 0, 22, 14),
                  gravity=(0, -G), restitution=0.0, friction=friction)
    trajectory = run(world, 1.0)
    travelled = (trajectory.positions[:, 0] - centre) @ -along   # down the slope
    t = trajectory.times
    a = max(G * (np.sin(theta) - friction * np.cos(theta)), 0.0)
    np.testing.assert_allclose(travelled, 0.5 * a * t ** 2, atol=1e-6)
    lifted = (trajectory.positions[:, 0] - centre) @ normal
    assert np.abs(lifted).max() < 1e-6                     # neither sinks in nor lifts off
    assert np.abs(trajectory.angles[:, 0] - theta).max() < 1e-9
    assert trajectory.segment_collisions.sum() == 0        # resting on it is not a collision


def test_a_box_bounces_on_a_shelf_and_the_events_name_the_segment():
    world = World([(5, 4.0)], polygons=[box(1.0, 0.5)], segments=[[0, 5, 2, 5], [3, 2, 8, 2]],
                  box=(0, 0, 10, 10), gravity=(0, -G), restitution=1.0)
    trajectory = run(world, 6.0)
    y = trajectory.positions[:, 0, 1]
    assert y.min() > 2.25 - 1e-9                           # never through the shelf at y = 2
    peaks = [y[k] for k in range(1, len(y) - 1) if y[k] >= y[k - 1] and y[k] > y[k + 1]]
    assert len(peaks) >= 3 and np.abs(np.array(peaks) - 4.0).max() < 0.01 * (4.0 - 2.25)
    impacts = trajectory.events.kind == SEGMENT
    assert impacts.sum() == trajectory.segment_collisions.sum() >= 3
    assert set(trajectory.events.j[impacts].tolist()) == {1}
    # midway between the box and the shelf where the step began: within half a step's fall of it
    half_step = 0.5 * np.sqrt(2 * G * (4.0 - 2.25)) / 60
    assert np.all(np.abs(trajectory.events.point[impacts, 1] - 2.0) <= half_step)
    assert N_WALLS == 4


def test_polygons_and_segments_meet_but_polygons_and_a_map_are_still_one_line():
    World([(5, 5)], polygons=[box(1, 1)], segments=[[0, 1, 9, 1]], box=(0, 0, 10, 10))
    image = np.full((20, 20), 255, np.uint8)
    image[:2, :] = 0   # a solid strip along the top
    solid_top = collisim.CollisionMap.from_image(image, cell=0.5)
    with pytest.raises(ValueError, match="collision maps"):
        World([(5, 5)], polygons=[box(1, 1)], map=solid_top, box=(0, 0, 10, 10))


@pytest.mark.parametrize("angle", [0.001, 0.003, -0.01])
def test_a_tilted_box_on_a_segment_has_the_manifold_of_the_same_line_as_a_wall(angle):
    """One corner a hair into the segment, the other raised within the margin: both points, as
    the floor's half-plane gives them (with the deepest corner alone, a box rocked and sank)."""
    from collisim.narrowphase.manifold import polygon_wall_manifold
    c, s = np.cos(angle), np.sin(angle)
    shape = np.asarray(box(1.0, 0.5)) @ np.array([[c, s], [-s, c]])
    lowest = shape[:, 1].min()
    start = np.array([0, len(shape)])
    on_segment = shape + (5.0, 1.0 - lowest - 0.001)
    m = polygon_segment_manifold(on_segment, start, 0, np.array([[1.0, 1.0, 9.0, 1.0]]), 0, 0.05)
    wall = polygon_wall_manifold(on_segment - (0.0, 1.0), start, 0, np.array([0.0, 0.0, 10.0, 10.0]), 2, 0.05)
    assert m[2] == wall[2] == 2
    raised = sorted(on_segment[:, 1] - 1.0)[1]    # the raised bottom corner's height over the segment
    np.testing.assert_allclose(sorted([m[3], m[6]]), sorted([0.001, -raised]), atol=1e-9)
    np.testing.assert_allclose(sorted([m[3], m[6]]), sorted([wall[3], wall[6]]), atol=1e-9)


@pytest.mark.parametrize("fps", [30, 60])
def test_a_column_of_boxes_rests_on_a_segment_as_on_the_floor(fps):
    h, n = 0.5, 6
    heights = [h / 2 + k * h * 1.001 for k in range(n)]

    def column(floor):
        segments = [[1.0, floor, 9.0, floor]] if floor else None
        world = World([(5.0, floor + y) for y in heights], polygons=[box(1.0, h)] * n, box=(0, 0, 10, 10),
                      gravity=(0, -G), restitution=0.0, friction=0.5, segments=segments)
        return run(world, 4.0, fps).positions - (0.0, floor)

    on_segment, on_floor = column(1.0), column(0.0)
    assert np.abs(on_segment[:, 0, 1] - h / 2).max() < 0.002 * h      # the bottom box does not sink
    assert np.abs(on_segment[-1] - on_floor[-1]).max() < 0.02 * h     # and the column ends as on the floor
