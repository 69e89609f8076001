"""Ray queries (collisim.raycast, raycast_many) against independent references.

* circles: the quadratic |o + t·u - c|² = r², solved in 50-digit decimal arithmetic (the code
  under test uses Box2D's closest-point form in float64);
* segments: shapely's intersection of the ray, as a LineString, with each segment;
* walls: the crossing times of the box's lines, in decimal;
* pymunk's Space.segment_query_first, wherever the ray starts outside every shape;
* brute force, for every broad phase (one parametrized fixture runs each test on all of them).
"""
import math
from decimal import Decimal, getcontext

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import collisim
from collisim import RayHit, RayHits, raycast, raycast_many
from collisim.broadphase import NAMES
from collisim.gas import lattice_gas
from collisim.narrowphase.statics import touching_segments
from collisim.queries import KIND_NAMES

getcontext().prec = 50
BODY, SEGMENT, MAP, WALL = (KIND_NAMES.index(kind) for kind in ("body", "segment", "map", "wall"))
TOLERANCE = 1e-9


@pytest.fixture(scope="module", params=NAMES)
def method(request):
    return request.param


# ------------------------------------------------------------------ worlds and rays

def gas_with_segments(n, box, n_segments, seed, length=3.0):
    """About n circles (lattice_gas) among n_segments random segments; the circles a segment
    would cut are left out."""
    positions, _, radii = lattice_gas(n, box=box, speed=1.0, seed=seed)
    rng = np.random.default_rng(seed)
    starts = rng.uniform(box[:2], box[2:], (n_segments, 2))
    angles = rng.uniform(0.0, np.pi, n_segments)
    ends = np.clip(starts + length * np.column_stack([np.cos(angles), np.sin(angles)]), box[:2], box[2:])
    segments = np.column_stack([starts, ends])
    free = np.ones(len(positions), bool)
    free[touching_segments(positions, radii, segments, np.asarray(box, float))[0][:, 0]] = False
    return collisim.World(positions[free], radii=radii[free], box=box, segments=segments)


def random_rays(rng, box, m, margin=2.0, reach=20.0):
    """m rays from around the box (some start outside it), unnormalised directions, half with an
    infinite max_distance."""
    box = np.asarray(box, float)
    origins = rng.uniform(box[:2] - margin, box[2:] + margin, (m, 2))
    angles = rng.uniform(0.0, 2 * np.pi, m)
    directions = np.column_stack([np.cos(angles), np.sin(angles)]) * rng.uniform(0.1, 10.0, (m, 1))
    max_distances = np.where(rng.random(m) < 0.5, np.inf, rng.uniform(0.0, reach, m))
    return origins, directions, max_distances


def units(directions):
    return directions / np.hypot(directions[:, 0], directions[:, 1])[:, None]


# ------------------------------------------------------------------ the references

def decimal_circle(origin, direction, centre, radius):
    """(t, point, normal, inside) of the ray against the circle, exactly (50 digits), or None."""
    ox, oy, dx, dy = (Decimal(float(v)) for v in (*origin, *direction))
    cx, cy, r = Decimal(float(centre[0])), Decimal(float(centre[1])), Decimal(float(radius))
    length = (dx * dx + dy * dy).sqrt()
    ux, uy = dx / length, dy / length
    sx, sy = ox - cx, oy - cy
    c = sx * sx + sy * sy - r * r
    if c < 0:
        return 0.0, np.array(origin, float), np.zeros(2), True
    b = sx * ux + sy * uy
    discriminant = b * b - c
    if discriminant < 0:
        return None
    t = -b - discriminant.sqrt()
    if t < 0:
        return None
    px, py = ox + t * ux, oy + t * uy
    return float(t), np.array([float(px), float(py)]), np.array([float((px - cx) / r), float((py - cy) / r)]), False


def decimal_walls(origin, direction, box):
    """(t, wall, point, normal, inside) of the ray leaving the box, exactly."""
    x0, y0, x1, y1 = box
    for wall, outside in enumerate((origin[0] < x0, origin[0] > x1, origin[1] < y0, origin[1] > y1)):
        if outside:
            return 0.0, wall, np.array(origin, float), np.zeros(2), True
    o = [Decimal(float(v)) for v in origin]
    d = [Decimal(float(v)) for v in direction]
    length = (d[0] * d[0] + d[1] * d[1]).sqrt()
    best = None
    for axis in range(2):
        if d[axis] == 0:
            continue
        wall = 2 * axis + (1 if d[axis] > 0 else 0)
        t = (Decimal(float(box[wall // 2 + 2 * (wall % 2)])) - o[axis]) / d[axis] * length
        if best is None or t < best[0]:
            best = (t, wall)
    t, wall = best
    point = np.array([float(o[0] + t * d[0] / length), float(o[1] + t * d[1] / length)])
    normal = np.zeros(2)
    normal[wall // 2] = 1.0 if wall % 2 == 0 else -1.0
    return float(t), wall, point, normal, False


def shapely_segments(segments, origins, unit_directions, reach):
    """Per ray the nearest intersection with each segment, by shapely: a list of (t, s, point,
    normal) per ray."""
    import shapely
    found = [[] for _ in origins]
    if len(segments) == 0:
        return found
    rays = shapely.linestrings(np.stack([origins, origins + reach[:, None] * unit_directions], axis=1))
    for s, (x0, y0, x1, y1) in enumerate(segments):
        crossings = shapely.intersection(rays, shapely.LineString([(x0, y0), (x1, y1)]))
        coordinates, ray_of = shapely.get_coordinates(crossings, return_index=True)
        normal = np.array([-(y1 - y0), x1 - x0]) / math.hypot(x1 - x0, y1 - y0)
        for point, k in zip(coordinates, ray_of):
            t = math.hypot(*(point - origins[k]))
            facing = normal if normal @ unit_directions[k] <= 0 else -normal
            found[k].append((t, s, point, facing))
    return found


def reference_hits(world, origins, directions, max_distances):
    """The expected closest hit of every ray: rows (t, inside, kind, index, point, normal), or None."""
    unit = units(directions)
    reach = np.minimum(max_distances, 1e3)
    near_segments = shapely_segments(world.segments, origins, unit, reach)
    # A float pre-filter of the circles whose line the ray may cross (generous margins); the
    # decimal solve decides.
    s = origins[:, None, :] - world.positions[None]
    b = np.einsum("mnk,mk->mn", s, unit)
    c = np.einsum("mnk,mnk->mn", s, s) - world.radii[None] ** 2
    maybe = (c < 1e-6) | ((b * b - c > -1e-6) & (b < 1e-6))
    expected = []
    for k in range(len(origins)):
        hits = []
        t, wall, point, normal, inside = decimal_walls(origins[k], directions[k], world.box)
        hits.append((t, inside, WALL, wall, point, normal))
        for i in np.flatnonzero(maybe[k]):
            found = decimal_circle(origins[k], directions[k], world.positions[i], world.radii[i])
            if found is not None:
                hits.append((found[0], found[3], BODY, i, found[1], found[2]))
        for t, segment, point, normal in near_segments[k]:
            hits.append((t, False, SEGMENT, segment, point, normal))
        hits = [hit for hit in hits if hit[0] <= max_distances[k]]
        expected.append(min(hits, key=lambda hit: (hit[0], not hit[1], hit[2], hit[3])) if hits else None)
    return expected


def assert_matches(found: RayHits, expected, tolerance=TOLERANCE):
    for k, hit in enumerate(expected):
        if hit is None:
            assert found.kinds[k] == -1 and found.distance[k] == np.inf, k
            continue
        t, inside, kind, index, point, normal = hit
        assert (found.kinds[k], found.indices[k], found.inside[k]) == (kind, index, inside), k
        assert abs(found.distance[k] - t) <= tolerance, (k, found.distance[k], t)
        np.testing.assert_allclose(found.points[k], point, rtol=0, atol=tolerance, err_msg=str(k))
        np.testing.assert_allclose(found.normals[k], normal, rtol=0, atol=1e-9, err_msg=str(k))


def assert_same_hits(a: RayHits, b: RayHits):
    for field in ("distance", "points", "normals", "kinds", "indices", "inside"):
        np.testing.assert_array_equal(getattr(a, field), getattr(b, field), err_msg=field)


# ------------------------------------------------------------------ against the references

BOX = (0.0, 0.0, 32.0, 18.0)


@pytest.fixture(scope="module")
def scene():
    """A world with circles, segments and walls, and 10 000 random rays through it."""
    world = gas_with_segments(60, BOX, 10, seed=3)
    rays = random_rays(np.random.default_rng(4), BOX, 10_000)
    return world, rays


@pytest.fixture(scope="module")
def expected(scene):
    return reference_hits(scene[0], *scene[1])


def test_random_rays_match_the_exact_references(scene, expected):
    world, rays = scene
    found = raycast_many(world, *rays, broadphase="brute")
    assert {KIND_NAMES[kind] for kind in found.kinds} == {"body", "segment", "wall"}
    assert found.inside.any() and (found.kinds == -1).any()
    assert_matches(found, expected)


def test_random_rays_match_pymunk(scene):
    pymunk = pytest.importorskip("pymunk")
    world, (origins, directions, max_distances) = scene
    space = pymunk.Space()
    for (x, y), r in zip(world.positions, world.radii):
        space.add(pymunk.Circle(space.static_body, float(r), offset=(float(x), float(y))))
    x0, y0, x1, y1 = world.box
    for a, b in [((x0, y0), (x0, y1)), ((x1, y0), (x1, y1)), ((x0, y0), (x1, y0)), ((x0, y1), (x1, y1))]:
        space.add(pymunk.Segment(space.static_body, a, b, 0.0))
    for ax, ay, bx, by in world.segments:
        space.add(pymunk.Segment(space.static_body, (ax, ay), (bx, by), 0.0))
    found = raycast_many(world, origins, directions, max_distances)
    unit = units(directions)
    centre_distance = np.hypot(*(origins[:, None, :] - world.positions[None]).transpose(2, 0, 1))
    outside = ((origins > world.box[:2]) & (origins < world.box[2:])).all(axis=1) \
        & (centre_distance > world.radii + 1e-6).all(axis=1)
    compared = 0
    for k in np.flatnonzero(outside):
        reach = min(max_distances[k], 100.0)
        info = space.segment_query_first(tuple(origins[k]), tuple(origins[k] + reach * unit[k]), 0.0,
                                         pymunk.ShapeFilter())
        if info is None:
            assert found.kinds[k] == -1, k
            continue
        compared += 1
        assert abs(info.alpha * reach - found.distance[k]) <= TOLERANCE, k
        np.testing.assert_allclose(found.points[k], tuple(info.point), rtol=0, atol=TOLERANCE)
        np.testing.assert_allclose(found.normals[k], tuple(info.normal), rtol=0, atol=TOLERANCE)
    assert compared > 5000


def test_every_broad_phase_finds_brute_forces_hits(method, scene):
    world, rays = scene
    assert_same_hits(raycast_many(world, *rays, broadphase=method), raycast_many(world, *rays, broadphase="brute"))


def test_broad_phases_visit_fewer_nodes_than_brute_force_tests(method):
    world = gas_with_segments(400, (0.0, 0.0, 60.0, 34.0), 20, seed=5)
    rays = random_rays(np.random.default_rng(6), world.box, 2000, margin=0.0, reach=15.0)
    brute = raycast_many(world, *rays, broadphase="brute")
    found = raycast_many(world, *rays, broadphase=method)
    assert_same_hits(found, brute)
    assert np.all(brute.tested == world.n)
    if method != "brute":
        assert found.visited.mean() < brute.tested.mean()
        assert found.tested.mean() < brute.tested.mean()


def test_far_from_the_origin(method):
    """A world 1e6 away from (0, 0): the rounding of every coordinate is 1e6 times coarser."""
    offset = np.array([1e6, -1e6])
    box = (offset[0], offset[1], offset[0] + 32.0, offset[1] + 18.0)
    world = gas_with_segments(60, box, 10, seed=8)
    rays = random_rays(np.random.default_rng(9), box, 1000)
    found = raycast_many(world, *rays, broadphase=method)
    assert_matches(found, reference_hits(world, *rays))
    assert_same_hits(found, raycast_many(world, *rays, broadphase="brute"))


def test_hits_are_consistent(scene):
    """Points lie at the distance along the unit direction; normals are unit and face the ray,
    except inside a solid, where they are (0, 0)."""
    world, (origins, directions, max_distances) = scene
    found = raycast_many(world, origins, directions, max_distances)
    hit = found.kinds >= 0
    unit = units(directions)
    np.testing.assert_allclose(found.points[hit], origins[hit] + found.distance[hit, None] * unit[hit], atol=1e-12)
    assert np.all(found.distance[hit] <= max_distances[hit])
    surface = hit & ~found.inside
    np.testing.assert_allclose(np.hypot(*found.normals[surface].T), 1.0, atol=1e-15)
    assert np.all(np.einsum("mk,mk->m", found.normals[surface], unit[surface]) <= 0.0)
    assert np.all(found.normals[found.inside] == 0.0) and np.all(found.distance[found.inside] == 0.0)
    assert np.all(found.indices[~hit] == -1) and np.isnan(found.points[~hit]).all()


def test_raycast_is_one_row_of_raycast_many(scene):
    world, (origins, directions, max_distances) = scene
    found = raycast_many(world, origins[:50], directions[:50], max_distances[:50])
    for k in range(50):
        hit = raycast(world, origins[k], directions[k], max_distances[k])
        if found.kinds[k] < 0:
            assert hit is None
            continue
        assert isinstance(hit, RayHit)
        assert (hit.distance, hit.kind, hit.index, hit.inside) == (
            found.distance[k], KIND_NAMES[found.kinds[k]], found.indices[k], found.inside[k])
        np.testing.assert_array_equal(hit.point, found.points[k])
        np.testing.assert_array_equal(hit.normal, found.normals[k])
        assert not hit.point.flags.writeable


# ------------------------------------------------------------------ edge cases

def one_circle(centre=(0.0, 0.0), radius=1.0, box=(-10.0, -10.0, 10.0, 10.0), **options):
    return collisim.World([centre], radii=radius, box=box, **options)


def hit_of(world, origin, direction, max_distance=math.inf, method="brute", **options):
    return raycast(world, origin, direction, max_distance, broadphase=method, **options)


def assert_hit(hit, distance, point, normal, kind, index, inside=False):
    assert hit is not None
    assert (hit.kind, hit.index, hit.inside) == (kind, index, inside)
    assert hit.distance == pytest.approx(distance, abs=1e-12)
    np.testing.assert_allclose(hit.point, point, atol=1e-12)
    np.testing.assert_allclose(hit.normal, normal, atol=1e-12)


def test_tangent_ray_grazes_a_circle(method):
    world = one_circle()
    assert_hit(hit_of(world, (-5.0, 1.0), (1.0, 0.0), method=method), 5.0, (0.0, 1.0), (0.0, 1.0), "body", 0)
    assert_hit(hit_of(world, (1.0, -5.0), (0.0, 3.0), method=method), 5.0, (1.0, 0.0), (1.0, 0.0), "body", 0)
    assert hit_of(world, (-5.0, 1.0 + 2.0 ** -40), (1.0, 0.0), method=method).kind == "wall"
    below = hit_of(world, (-5.0, 1.0 - 2.0 ** -40), (1.0, 0.0), method=method)
    assert below.kind == "body" and below.distance == pytest.approx(5.0 - math.sqrt(2.0 ** -39), rel=1e-6)


def test_ray_through_a_segment_end_point_and_a_shared_vertex():
    world = collisim.World(np.zeros((0, 2)), box=(-10.0, -10.0, 10.0, 10.0),
                           segments=[[0.0, 0.0, 2.0, 0.0], [2.0, 0.0, 4.0, 2.0]])
    assert_hit(hit_of(world, (0.0, -3.0), (0.0, 1.0)), 3.0, (0.0, 0.0), (0.0, -1.0), "segment", 0)
    assert_hit(hit_of(world, (-1.0, -1.0), (1.0, 1.0)), math.sqrt(2.0), (0.0, 0.0), (0.0, -1.0), "segment", 0)
    # Both segments end at (2, 0): the tie goes to the smaller index.
    assert_hit(hit_of(world, (2.0, -3.0), (0.0, 1.0)), 3.0, (2.0, 0.0), (0.0, -1.0), "segment", 0)
    # Along segment 0's line: its end and segment 1's vertex tie, segment 0 (edge on) wins.
    assert_hit(hit_of(world, (5.0, 0.0), (-1.0, 0.0)), 3.0, (2.0, 0.0), (1.0, 0.0), "segment", 0)
    assert_hit(hit_of(world, (-1.0, 3.0), (1.0, -1.0)), math.sqrt(18.0), (2.0, 0.0), (0.0, 1.0), "segment", 0)
    # Along segment 1's line, from beyond its far end.
    assert_hit(hit_of(world, (5.0, 3.0), (-1.0, -1.0)), math.sqrt(2.0), (4.0, 2.0),
               (math.sqrt(0.5), math.sqrt(0.5)), "segment", 1)


def test_ray_along_a_segment():
    world = collisim.World(np.zeros((0, 2)), box=(-10.0, -10.0, 10.0, 10.0), segments=[[0.0, 0.0, 2.0, 0.0]])
    # Along its line: the nearer end point, normal against the ray.
    assert_hit(hit_of(world, (-3.0, 0.0), (1.0, 0.0)), 3.0, (0.0, 0.0), (-1.0, 0.0), "segment", 0)
    assert_hit(hit_of(world, (5.0, 0.0), (-2.0, 0.0)), 3.0, (2.0, 0.0), (1.0, 0.0), "segment", 0)
    assert_hit(hit_of(world, (1.0, 0.0), (1.0, 0.0)), 0.0, (1.0, 0.0), (-1.0, 0.0), "segment", 0)
    # Starting on it and crossing: distance 0, the perpendicular facing the ray, not inside.
    assert_hit(hit_of(world, (1.0, 0.0), (0.0, 1.0)), 0.0, (1.0, 0.0), (0.0, -1.0), "segment", 0)
    assert_hit(hit_of(world, (1.0, 0.0), (0.0, -1.0)), 0.0, (1.0, 0.0), (0.0, 1.0), "segment", 0)
    # Parallel beside it, and along its line but pointing away: missed.
    assert hit_of(world, (-3.0, 2.0 ** -60), (1.0, 0.0)).kind == "wall"
    assert hit_of(world, (-3.0, 0.0), (-1.0, 0.0)).kind == "wall"


def test_starting_on_a_circle(method):
    world = one_circle(radius=5.0, box=(-20.0, -20.0, 20.0, 20.0))
    into, away, tangent = (-3.0, -4.0), (3.0, 4.0), (-4.0, 3.0)
    assert_hit(hit_of(world, (3.0, 4.0), into, method=method), 0.0, (3.0, 4.0), (0.6, 0.8), "body", 0)
    assert hit_of(world, (3.0, 4.0), away, method=method).kind == "wall"
    assert_hit(hit_of(world, (3.0, 4.0), tangent, method=method), 0.0, (3.0, 4.0), (0.6, 0.8), "body", 0)


def test_starting_on_a_wall():
    world = collisim.World(np.zeros((0, 2)), box=(0.0, 0.0, 10.0, 10.0))
    assert_hit(hit_of(world, (0.0, 5.0), (-1.0, 0.0)), 0.0, (0.0, 5.0), (1.0, 0.0), "wall", 0)
    assert_hit(hit_of(world, (0.0, 5.0), (1.0, 0.0)), 10.0, (10.0, 5.0), (-1.0, 0.0), "wall", 1)
    assert_hit(hit_of(world, (0.0, 5.0), (0.0, 1.0)), 0.0, (0.0, 5.0), (1.0, 0.0), "wall", 0)  # sliding along
    assert_hit(hit_of(world, (5.0, 10.0), (1.0, 1.0)), 0.0, (5.0, 10.0), (0.0, -1.0), "wall", 3)
    assert_hit(hit_of(world, (0.0, 0.0), (-1.0, -1.0)), 0.0, (0.0, 0.0), (1.0, 0.0), "wall", 0)  # a corner
    assert_hit(hit_of(world, (5.0, 5.0), (1.0, 1.0)), 5.0 * math.sqrt(2.0), (10.0, 10.0), (-1.0, 0.0), "wall", 1)


class SquareMap:
    """A stand-in for a collision map: the solid square [x0, x1] × [y0, y1], its outline as
    four segments, and its signed distance (negative inside)."""

    def __init__(self, x0, y0, x1, y1):
        self.segments = np.array([[x0, y0, x1, y0], [x1, y0, x1, y1], [x1, y1, x0, y1], [x0, y1, x0, y0]])
        self.centre = np.array([x0 + x1, y0 + y1]) / 2
        self.half = np.array([x1 - x0, y1 - y0]) / 2

    def distance(self, points):
        q = np.abs(np.asarray(points, float) - self.centre) - self.half
        return np.hypot(*np.maximum(q, 0.0).T) + np.minimum(q.max(axis=1), 0.0)


def test_starting_inside(method):
    world = collisim.World([[2.0, 2.0], [6.0, 2.0]], radii=1.0, box=(0.0, 0.0, 10.0, 10.0))
    world.map = SquareMap(4.0, 6.0, 8.0, 9.0)
    for origin, kind, index in [((6.5, 2.2), "body", 1), ((-1.0, 5.0), "wall", 0), ((11.0, -1.0), "wall", 1),
                                ((5.0, 11.0), "wall", 3), ((7.5, 6.2), "map", 0), ((7.9, 8.0), "map", 1)]:
        hit = hit_of(world, origin, (1.0, 0.5), method=method)
        assert_hit(hit, 0.0, origin, (0.0, 0.0), kind, index, inside=True)


def test_the_map_outline_is_hit_like_segments(method):
    world = collisim.World([[2.0, 2.0]], radii=1.0, box=(0.0, 0.0, 10.0, 10.0), segments=[[1.0, 7.0, 1.0, 9.0]])
    world.map = SquareMap(4.0, 6.0, 8.0, 9.0)
    assert_hit(hit_of(world, (2.0, 7.0), (1.0, 0.0), method=method), 2.0, (4.0, 7.0), (-1.0, 0.0), "map", 3)
    assert_hit(hit_of(world, (6.0, 2.0), (0.0, 1.0), method=method), 4.0, (6.0, 6.0), (0.0, -1.0), "map", 0)
    assert_hit(hit_of(world, (2.0, 8.0), (-1.0, 0.0), method=method), 1.0, (1.0, 8.0), (1.0, 0.0), "segment", 0)


def test_max_distance_is_a_closed_interval():
    world = one_circle(centre=(5.0, 0.0), segments=[[-3.0, -1.0, -3.0, 1.0]])
    for direction, distance, kind in [((1.0, 0.0), 4.0, "body"), ((-1.0, 0.0), 3.0, "segment"),
                                      ((0.0, 1.0), 10.0, "wall")]:
        assert hit_of(world, (0.0, 0.0), direction, distance).kind == kind
        assert hit_of(world, (0.0, 0.0), direction, np.nextafter(distance, 0.0)) is None
    assert hit_of(world, (4.0, 0.0), (1.0, 0.0), 0.0).distance == 0.0  # touching at distance 0


def test_duplicate_and_coincident_bodies(method):
    world = collisim.World([[x, 5.0] for x in range(1, 10, 2)], radii=0.5, box=(0.0, 0.0, 10.0, 10.0))
    positions = world.positions.copy()
    positions[[1, 3, 4]] = positions[2]  # four bodies on one spot: 1, 2, 3, 4
    assert_hit(hit_of(world, (0.0, 5.0), (1.0, 0.0), method=method, positions=positions),
               0.5, (0.5, 5.0), (-1.0, 0.0), "body", 0)
    assert_hit(hit_of(world, (5.0, 0.0), (0.0, 1.0), method=method, positions=positions),
               4.5, (5.0, 4.5), (0.0, -1.0), "body", 1)
    assert_hit(hit_of(world, (5.0, 5.0), (0.0, 1.0), method=method, positions=positions),
               0.0, (5.0, 5.0), (0.0, 0.0), "body", 1, inside=True)
    assert_hit(hit_of(world, (10.0, 5.0), (-1.0, 0.0), method=method, positions=positions),
               4.5, (5.5, 5.0), (1.0, 0.0), "body", 1)


def test_empty_world_has_walls_only(method):
    world = collisim.World(np.zeros((0, 2)), box=(0.0, 0.0, 10.0, 10.0))
    rays = random_rays(np.random.default_rng(1), world.box, 200)
    found = raycast_many(world, *rays, broadphase=method)
    assert set(found.kinds.tolist()) <= {WALL, -1} and (found.kinds == WALL).any()
    assert np.all(found.visited == 0) and np.all(found.tested == 0)
    assert_matches(found, reference_hits(world, *rays))


def test_no_rays():
    found = raycast_many(one_circle(), np.zeros((0, 2)), np.zeros((0, 2)))
    assert len(found) == 0 and found.distance.shape == (0,) and found.points.shape == (0, 2)
    assert found.kinds.dtype == np.int8 and found.indices.dtype == np.int64 and found.inside.dtype == bool


@pytest.mark.parametrize("origin, direction, max_distance, message", [
    ((0.0, 0.0), (0.0, 0.0), 1.0, "direction must be non-zero"),
    ((0.0, 0.0), (np.nan, 1.0), 1.0, "direction must be finite"),
    ((np.inf, 0.0), (1.0, 0.0), 1.0, "origin must be finite"),
    ((0.0, 0.0), (1.0, 0.0), -1.0, "max_distance must be >= 0"),
    ((0.0, 0.0), (1.0, 0.0), np.nan, "max_distance must be >= 0"),
])
def test_bad_rays_are_one_clear_line(origin, direction, max_distance, message):
    world = one_circle()
    with pytest.raises(ValueError, match=message):
        raycast(world, origin, direction, max_distance)
    origins, directions = np.array([[1.0, 1.0], origin]), np.array([[1.0, 0.0], direction])
    with pytest.raises(ValueError, match=f"ray 1: .*{message}"):
        raycast_many(world, origins, directions, [1.0, max_distance])


def test_bad_arguments():
    world = one_circle()
    with pytest.raises(ValueError, match="shape"):
        raycast_many(world, np.zeros((3, 2)), np.ones((2, 2)))
    with pytest.raises(ValueError, match="max_distance"):
        raycast_many(world, np.zeros((3, 2)), np.ones((3, 2)), [1.0, 2.0])
    with pytest.raises(ValueError, match="unknown broad phase"):
        raycast(world, (0.0, 0.0), (1.0, 0.0), broadphase="octree")
    with pytest.raises(ValueError, match="positions"):
        raycast(world, (0.0, 0.0), (1.0, 0.0), positions=np.zeros((2, 2)))


# ------------------------------------------------------------------ properties

small = st.integers(-6, 6).map(float)
component = st.one_of(st.integers(-3, 3).map(float), st.floats(-1, 1, allow_nan=False))


@st.composite
def small_scenes(draw):
    """Circles (which may overlap or coincide: given as positions=), segments and rays on a small
    integer lattice, where exact ties (grazing, vertices, coincident shapes) are common."""
    n = draw(st.integers(0, 12))
    radii = draw(st.lists(st.sampled_from([0.5, 1.0, 1.5]), min_size=n, max_size=n))
    centres = draw(st.lists(st.tuples(small, small), min_size=n, max_size=n))
    segments = draw(st.lists(st.tuples(small, small, small, small), max_size=5))
    world = collisim.World([[3.0 * k - 60.0, 0.0] for k in range(n)] or np.zeros((0, 2)),
                           radii=radii or 1.0, box=(-80.0, -8.0, 80.0, 8.0), segments=segments or None)
    origins = draw(st.lists(st.tuples(small, small), min_size=1, max_size=8))
    directions = draw(st.lists(st.tuples(component, component).filter(lambda d: d != (0.0, 0.0)),
                               min_size=len(origins), max_size=len(origins)))
    max_distance = draw(st.one_of(st.just(math.inf), st.integers(0, 12).map(float)))
    return world, np.array(centres).reshape(-1, 2), np.array(origins), np.array(directions), max_distance


@settings(max_examples=80, deadline=None)
@given(scene=small_scenes())
def test_every_broad_phase_agrees_on_small_lattice_scenes(method, scene):
    world, centres, origins, directions, max_distance = scene
    found = raycast_many(world, origins, directions, max_distance, broadphase=method, positions=centres)
    assert_same_hits(found, raycast_many(world, origins, directions, max_distance, broadphase="brute",
                                         positions=centres))
    unit = units(directions)
    surface = (found.kinds >= 0) & ~found.inside
    assert np.all(np.einsum("mk,mk->m", found.normals[surface], unit[surface]) <= 0.0)
    assert np.all(found.distance[found.kinds >= 0] <= max_distance)


def test_auto_uses_the_broad_phase_the_step_would():
    positions, _, radii = lattice_gas(250, box=BOX, speed=1.0, seed=7)
    gas = collisim.World(positions, radii=radii, box=BOX)
    assert raycast_many(gas, [[1.0, 1.0]], [[1.0, 0.0]]).broadphase == "grid"
    assert raycast_many(one_circle(), [[1.0, 1.0]], [[1.0, 0.0]]).broadphase == "brute"
    assert RayHits.KIND_NAMES == ("body", "segment", "map", "wall")


def test_bench_rays_runs():
    from collisim.analysis.bench.rays import bench_rays, format_rays
    rows = bench_rays(count=300, repeats=1, broadphases=("brute", "grid"))
    assert [row["method"] for row in rows] == ["brute", "grid", "pymunk"]
    assert all(row["agrees"] == 1.0 for row in rows) and rows[1]["visited"] < rows[0]["tested"]
    assert "pymunk" in format_rays(rows)
