"""Rays see polygons: the first hit on a convex polygon body, its point, distance and normal,
against shapely's intersection of the ray's segment with the polygon; an origin inside a
polygon is inside; every broad phase gives the same answer."""
import numpy as np
import pytest
from shapely.geometry import LineString, Point, Polygon

import collisim
from collisim.broadphase import NAMES
from collisim.shapes import box, regular

BOX = (0.0, 0.0, 40.0, 40.0)
REACH = 30.0


def polygon_world(seed=4):
    """Boxes, triangles and hexagons at random turns on a lattice, apart from each other."""
    rng = np.random.default_rng(seed)
    shapes = [box(2.0, 1.0), regular(3, 1.1), regular(6, 0.9), box(0.6, 2.2)]
    centres = np.array([(x, y) for x in np.arange(5.0, 40.0, 6.0) for y in np.arange(5.0, 40.0, 6.0)])
    polygons = [shapes[k % len(shapes)] for k in range(len(centres))]
    return collisim.World(centres, polygons=polygons, angles=rng.uniform(0, 2 * np.pi, len(centres)), box=BOX)


def shapely_polygons(world):
    vertices = world.placed_vertices()
    return [Polygon(vertices[world.vertex_start[i]:world.vertex_start[i + 1]]) for i in range(world.n)]


def first_hit(shapes, origin, unit, reach):
    """(distance, body) of the nearest point where the segment origin + [0, reach]·unit meets a
    polygon (shapely), or (inf, -1)."""
    ray = LineString([origin, origin + reach * unit])
    best = (np.inf, -1)
    for i, shape in enumerate(shapes):
        met = ray.intersection(shape)
        if not met.is_empty:
            points = np.array([c for geometry in getattr(met, "geoms", [met]) for c in geometry.coords])
            best = min(best, (float(np.min((points - origin) @ unit)), i))
    return best


@pytest.fixture(scope="module")
def rays():
    rng = np.random.default_rng(11)
    world = polygon_world()
    shapes = shapely_polygons(world)
    origins = rng.uniform(0.5, 39.5, (400, 2))
    outside = np.array([not any(s.intersects(Point(o)) for s in shapes) for o in origins])
    origins = origins[outside]
    angles = rng.uniform(0, 2 * np.pi, len(origins))
    units = np.column_stack([np.cos(angles), np.sin(angles)])
    return world, shapes, origins, units


@pytest.mark.parametrize("name", NAMES)
def test_every_ray_hits_the_polygon_shapely_finds_first_with_its_edge_normal(rays, name):
    world, shapes, origins, units = rays
    found = collisim.raycast_many(world, origins, units, REACH, broadphase=name)
    bodies = found.kinds == found.KIND_NAMES.index("body")
    hits = 0
    for k in range(len(origins)):
        distance, body = first_hit(shapes, origins[k], units[k], REACH)
        if body < 0:
            assert not bodies[k], k
            continue
        hits += 1
        assert bodies[k] and found.indices[k] == body, k
        assert found.distance[k] == pytest.approx(distance, abs=1e-9), k
        point, normal = found.points[k], found.normals[k]
        assert shapes[body].exterior.distance(Point(point)) < 1e-9
        assert np.hypot(*normal) == pytest.approx(1.0) and normal @ units[k] <= 0.0
        # the normal is the outward normal of the edge the point lies on
        inward = Point(point - 1e-6 * normal)
        outward = Point(point + 1e-6 * normal)
        assert shapes[body].contains(inward) and not shapes[body].contains(outward)
        assert not found.inside[k]
    assert hits > 100   # the rays do meet polygons (found none before: rays were blind to them)


def test_a_ray_at_a_box_hits_its_face_not_the_wall_behind_it():
    world = collisim.World([[10.0, 5.0]], polygons=[box(2.0, 2.0)], box=(0, 0, 20, 10))
    hit = collisim.raycast(world, (6.0, 5.0), (1.0, 0.0))
    assert (hit.kind, hit.index) == ("body", 0)
    assert hit.distance == pytest.approx(3.0, abs=1e-12)
    np.testing.assert_allclose(hit.normal, [-1.0, 0.0], atol=1e-12)


def test_a_ray_from_inside_a_polygon_is_inside():
    world = collisim.World([[10.0, 5.0]], polygons=[regular(6, 1.0)], angles=[0.3], box=(0, 0, 20, 10))
    inside = collisim.raycast(world, (10.2, 5.1), (0.0, 1.0))
    assert (inside.kind, inside.inside, inside.distance) == ("body", True, 0.0)
    np.testing.assert_array_equal(inside.normal, [0.0, 0.0])


@pytest.mark.parametrize("direction, expected", [((1.0, 0.0), ("body", 0.0, [-1.0, 0.0])),     # into it
                                                 ((0.0, 1.0), ("body", 0.0, [-1.0, 0.0])),     # along its edge
                                                 ((-1.0, 0.0), ("wall", 9.0, [1.0, 0.0])),     # out of it
                                                 ((0.0, -1.0), ("body", 0.0, [-1.0, 0.0]))])   # along, down
def test_a_ray_from_a_polygons_edge_touches_it_going_in_or_along_and_leaves_it_going_out(direction, expected):
    world = collisim.World([[10.0, 5.0]], polygons=[box(2.0, 2.0)], box=(0, 0, 20, 10))   # left edge x = 9
    hit = collisim.raycast(world, (9.0, 5.0), direction)
    assert (hit.kind, hit.distance) == expected[:2] and not hit.inside
    np.testing.assert_array_equal(hit.normal, expected[2])


def test_a_ray_from_a_corner_pointing_out_along_an_edges_line_misses_the_polygon():
    world = collisim.World([[10.0, 5.0]], polygons=[box(2.0, 2.0)], box=(0, 0, 20, 10))
    assert collisim.raycast(world, (9.0, 4.0), (0.0, -1.0)).kind == "wall"


def test_a_recorded_frame_casts_at_its_own_turns():
    """A polygon turned by a quarter turn at a recorded frame: the ray meets its long side."""
    world = collisim.World([[10.0, 5.0]], polygons=[box(4.0, 1.0)], box=(0, 0, 20, 10))
    flat = collisim.raycast(world, (10.0, 9.0), (0.0, -1.0))
    turned = collisim.raycast(world, (10.0, 9.0), (0.0, -1.0), angles=[np.pi / 2])
    assert flat.distance == pytest.approx(3.5) and turned.distance == pytest.approx(2.0)
    with pytest.raises(ValueError, match="angles must be 1 finite numbers"):
        collisim.raycast(world, (10.0, 9.0), (0.0, -1.0), angles=[np.nan])


@pytest.mark.parametrize("name", NAMES)
def test_skip_inside_looks_past_the_bodies_that_hold_the_origin_and_nothing_else(name):
    """Rays from inside polygons and circles with skip_inside=True answer as the same rays in the
    world without the bodies that hold their origins (brute force by removal), whichever broad
    phase searches; without it they are inside."""
    rng = np.random.default_rng(5)
    polygons = polygon_world()
    positions = np.vstack([polygons.positions, [[8.0, 8.0], [20.0, 14.0]]])
    shapes = [box(2.0, 1.0), regular(3, 1.1), regular(6, 0.9), box(0.6, 2.2)]
    listed = [shapes[k % len(shapes)] for k in range(polygons.n)] + [None, None]
    world = collisim.World(positions, radii=1.2, polygons=listed, angles=np.append(polygons.angles, [0.0, 0.0]),
                           box=BOX)
    holders = [0, 9, 23, world.n - 2, world.n - 1]
    origins = world.positions[holders] + rng.uniform(-0.2, 0.2, (len(holders), 2))
    directions = rng.normal(size=(len(holders), 2))
    held = collisim.raycast_many(world, origins, directions, REACH, name)
    assert held.inside.all() and (held.indices == holders).all()
    looked = collisim.raycast_many(world, origins, directions, REACH, name, skip_inside=True)
    for k, holder in enumerate(holders):
        keep = np.arange(world.n) != holder
        alone = collisim.World(world.positions[keep], radii=world.radii[keep],
                               polygons=[listed[i] for i in np.flatnonzero(keep)], angles=world.angles[keep], box=BOX)
        expected = collisim.raycast(alone, origins[k], directions[k], REACH)
        assert not looked.inside[k] and looked.distance[k] == pytest.approx(expected.distance, abs=1e-12)
        index = expected.index + (expected.kind == "body" and expected.index >= holder)
        assert (looked.KIND_NAMES[looked.kinds[k]], looked.indices[k]) == (expected.kind, index)
        np.testing.assert_allclose(looked.normals[k], expected.normal, atol=1e-12)
