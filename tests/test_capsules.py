"""Capsules (shapes.capsule): their mass, their manifolds and rays against shapely's exact
distances, and their motion through the public API against closed forms, conservation laws and
pymunk's Segment with a radius (the same shape)."""
import math

import numpy as np
import pytest
from shapely.geometry import LineString, Point, Polygon

import collisim
from collisim import Scene, World
from collisim.model.trajectory import load_trajectory
from collisim.narrowphase.capsules import capsule_capsule, capsule_circle, capsule_halfplane, rounded_cores
from collisim.narrowphase.ray import ray_body
from collisim.shapes import Capsule, box, capsule, regular

G, FPS = 9.81, 60.0
BOX = (0.0, 0.0, 10.0, 10.0)


def run(world, seconds, fps=FPS):
    return collisim.simulate(Scene(world=world, fps=fps, seconds=seconds))


def core(rng):
    c, turn, half = rng.uniform(-1, 1, 2), rng.uniform(0, 2 * np.pi), rng.uniform(0.1, 1.5)
    u = np.array([np.cos(turn), np.sin(turn)])
    return np.ascontiguousarray([c - half * u, c + half * u])


def test_mass_and_moment_are_the_capsules_own():
    length, r = 2.0, 0.5
    world = World([(5, 5)], shapes=[capsule(length, r)], box=BOX)
    assert world.masses[0] == pytest.approx(2 * r * length + np.pi * r * r, rel=1e-14)
    # the polar moment by brute force: a fine grid of cells inside the capsule
    h = 1e-3
    x, y = np.meshgrid(np.arange(-1.5, 1.5, h) + h / 2, np.arange(-0.5, 0.5, h) + h / 2)
    inside = np.hypot(np.maximum(np.abs(x) - length / 2, 0.0), y) <= r
    brute = ((x * x + y * y) * inside).sum() * h * h
    assert world.inertias[0] == pytest.approx(brute, rel=1e-4)
    assert world.radii[0] == length / 2 + r and world.capsule_radii[0] == r
    lo, hi = world.extents()
    np.testing.assert_allclose([lo[0], hi[0]], [[3.5, 4.5], [6.5, 5.5]], atol=1e-15)


def _check_gap_and_points(m, first, r1, second, r2):
    """A speculative manifold m of shapes apart: depth0 is minus their gap, and its deepest
    point, moved half the depth either way along the normal, lies on each surface."""
    gap = first.distance(second) - r1 - r2
    nx, ny, count, depth, px, py = m[:6]
    assert count >= 1 and -depth == pytest.approx(gap, abs=1e-9)
    on_first = Point(px + 0.5 * depth * nx, py + 0.5 * depth * ny)
    on_second = Point(px - 0.5 * depth * nx, py - 0.5 * depth * ny)
    assert first.distance(on_first) - r1 == pytest.approx(0.0, abs=1e-9)
    assert second.distance(on_second) - r2 == pytest.approx(0.0, abs=1e-9)


def test_manifolds_against_shapely():
    rng = np.random.default_rng(7)
    checked = 0
    for trial in range(1200):
        a, ra = core(rng), rng.uniform(0.1, 0.8)
        kind = trial % 4
        if kind == 0:      # capsule–capsule
            b, rb = core(rng) + rng.uniform(-1, 1, 2), rng.uniform(0.1, 0.8)
            m, first, r1, second, r2 = capsule_capsule(*a.ravel(), ra, *b.ravel(), rb, 9.0), a, ra, b, rb
            first, second = LineString(first), LineString(second)
        elif kind == 1:    # capsule–segment: a capsule of radius 0
            b = core(rng) + rng.uniform(-1, 1, 2)
            m, first, r1, second, r2 = capsule_capsule(*a.ravel(), ra, *b.ravel(), 0.0, 9.0), LineString(a), ra, \
                LineString(b), 0.0
        elif kind == 2:    # polygon–capsule
            p = np.ascontiguousarray(regular(int(rng.integers(3, 7)), rng.uniform(0.3, 1.2)) + rng.uniform(-2, 2, 2))
            m, first, r1, second, r2 = rounded_cores(p, a, 0.0, ra, 9.0), Polygon(p), 0.0, LineString(a), ra
        else:              # capsule–circle
            c, rc = rng.uniform(-2.5, 2.5, 2), rng.uniform(0.1, 0.8)
            m, first, r1, second, r2 = capsule_circle(*a.ravel(), ra, *c, rc, 9.0), LineString(a), ra, Point(c), rc
        if first.distance(second) - r1 - r2 > 1e-9:
            _check_gap_and_points(m, first, r1, second, r2)
            checked += 1
        else:   # overlapping: a contact, the normal a unit vector, no negative depth
            assert m[2] >= 1 and m[3] >= -1e-9 and math.hypot(m[0], m[1]) == pytest.approx(1.0, abs=1e-12)
    assert checked > 500


def test_capsules_side_by_side_touch_at_two_points():
    # a capsule lying on another: the overlap of their lengths, both ends of it
    m = capsule_capsule(0.0, 0.0, 2.0, 0.0, 0.5, 1.0, 0.9, 4.0, 0.9, 0.4, 0.1)
    assert m[2] == 2 and (m[0], m[1]) == pytest.approx((0.0, 1.0))
    assert sorted([m[4], m[7]]) == pytest.approx([1.0, 2.0]) and m[3] == pytest.approx(0.0, abs=1e-15)


def test_a_capsule_against_a_floor_has_a_point_under_each_cap():
    a = np.array([[1.0, 0.7], [3.0, 0.6]])       # a wall's solid y <= 0, its normal (0, 1)
    m = capsule_halfplane(a, 0.5, 0.0, 1.0, 0.0, 0.5)
    assert m[2] == 2 and (m[0], m[1]) == (0.0, -1.0)
    assert {round(m[3], 12), round(m[6], 12)} == {-0.1, -0.2}
    # midway between each cap's lowest point and the floor
    np.testing.assert_allclose(sorted([(m[4], m[5]), (m[7], m[8])]), [(1.0, 0.1), (3.0, 0.05)], atol=1e-12)


def test_rays_hit_the_capsule_outline_first():
    rng = np.random.default_rng(3)
    world = World([(5, 5)], shapes=[capsule(2.0, 0.6)], angles=0.7, box=BOX)
    placed, start = world.placed_vertices(), world.vertex_start
    outline = LineString(placed[:2])
    hits = 0
    for _ in range(400):
        o = rng.uniform(1, 9, 2)
        turn = rng.uniform(0, 2 * np.pi)
        u = np.array([np.cos(turn), np.sin(turn)])
        t, nx, ny, inside = ray_body(world.shapes, world.positions, world.radii, placed, start, 0, *o, *u)
        if outline.distance(Point(o)) < 0.6:
            assert inside and t == 0.0
            continue
        if t == np.inf:   # a miss: the whole ray stays farther than r from the core
            assert LineString([o, o + 20 * u]).distance(outline) > 0.6 - 1e-9
            continue
        hits += 1
        hit = o + t * u
        assert outline.distance(Point(hit)) == pytest.approx(0.6, abs=1e-9)    # on the outline
        assert LineString([o, hit]).distance(outline) == pytest.approx(0.6, abs=1e-9)   # nothing before
        q = outline.interpolate(outline.project(Point(hit)))
        np.testing.assert_allclose([nx, ny], (hit - np.array(q.coords[0])) / 0.6, atol=1e-7)
    assert hits > 50


def test_a_capsule_dropped_flat_comes_to_rest_at_its_radius_without_turning():
    world = World([(5, 2.0)], shapes=[capsule(2.0, 0.5)], box=BOX, gravity=(0, -G), restitution=0.0, friction=0.5)
    trajectory = run(world, 2.0)
    assert trajectory.positions[-1, 0, 1] == pytest.approx(0.5, abs=1e-3)
    assert np.abs(trajectory.angles[:, 0]).max() < 1e-9
    assert np.hypot(*trajectory.velocities[-1, 0]) < 1e-3


def test_a_capsule_dropped_at_an_angle_settles_flat():
    world = World([(5, 3.0)], shapes=[capsule(2.0, 0.5)], angles=0.5, box=BOX, gravity=(0, -G),
                  restitution=0.0, friction=0.5)
    trajectory = run(world, 4.0)
    angle = trajectory.angles[-1, 0]
    assert abs(math.remainder(angle, math.pi)) < 1e-3    # lying on its side
    assert trajectory.positions[-1, 0, 1] == pytest.approx(0.5, abs=1e-3)


def test_a_capsule_slides_down_a_slope_at_g_sin_minus_mu_cos():
    theta, mu = math.radians(30.0), 0.3
    c, s = math.cos(theta), math.sin(theta)
    slope = [[1.0, 7.0, 9.0, 7.0 - 8.0 * s / c]]          # a segment falling to the right
    r, length = 0.3, 1.0
    x0 = 3.0                                              # lying along the slope, touching it
    y0 = 7.0 - (x0 - 1.0) * s / c + r / c
    world = World([(x0, y0)], shapes=[capsule(length, r)], angles=-theta, segments=slope, box=BOX,
                  gravity=(0, -G), restitution=0.0, friction=mu)
    trajectory = run(world, 0.8)
    v = trajectory.velocities[:, 0]
    along = v[:, 0] * c - v[:, 1] * s                    # down the slope
    times = trajectory.times
    fit = np.polyfit(times[10:], along[10:], 1)[0]
    assert fit == pytest.approx(G * (s - mu * c), rel=0.02)
    assert np.abs(trajectory.angles[:, 0] + theta).max() < 1e-3   # it slides, it does not roll


def test_a_circle_hitting_a_capsule_head_on_keeps_momentum_and_applies_e():
    e = 0.5
    world = World([(2.0, 5.0), (6.0, 5.0)], velocities=[(4.0, 0.0), (0.0, 0.0)], radii=0.5,
                  shapes=[None, capsule(2.0, 0.5)], box=BOX, restitution=e)
    trajectory = run(world, 1.0)
    assert trajectory.pair_collisions.sum() >= 1
    m, v = world.masses, trajectory.velocities[-1]
    momentum = m @ v
    np.testing.assert_allclose(momentum, m @ world.velocities, atol=1e-12)
    assert v[1, 0] - v[0, 0] == pytest.approx(e * 4.0, rel=1e-9)
    assert abs(trajectory.angular_velocities[-1, 1]) < 1e-12      # along its axis: no turn


def test_capsules_colliding_elastically_keep_their_energy():
    rng = np.random.default_rng(5)
    positions = [(2.0 + 3.0 * (k % 3), 2.0 + 3.0 * (k // 3)) for k in range(6)]
    world = World(positions, velocities=rng.uniform(-3, 3, (6, 2)), angles=rng.uniform(0, 3, 6),
                  angular_velocities=rng.uniform(-2, 2, 6), shapes=[capsule(1.2, 0.4)] * 6, box=(0, 0, 10, 8),
                  restitution=1.0)
    trajectory = run(world, 4.0)
    kinetic = trajectory.kinetic_energy()
    collisions = trajectory.pair_collisions.sum() + trajectory.wall_collisions.sum()
    assert collisions >= 10
    assert np.abs(kinetic - kinetic[0]).max() <= 1e-9 * collisions * kinetic[0]


def test_a_capsule_never_passes_a_segment():
    world = World([(2.0, 5.0)], velocities=[(8.0, 0.5)], angular_velocities=[6.0], shapes=[capsule(1.0, 0.2)],
                  segments=[[5.0, 1.0, 5.0, 9.0]], box=BOX, restitution=1.0)
    trajectory = run(world, 2.0)
    placed = [world.placed_vertices(trajectory.positions[f], trajectory.angles[f]) for f in range(len(trajectory.times))]
    assert max(p[:, 0].max() for p in placed) < 5.0 - 0.2 + 1e-6   # every cap centre stays left of it
    assert trajectory.segment_collisions.sum() >= 1


def test_a_capsule_world_round_trips_through_a_trajectory_file(tmp_path):
    world = World([(2, 2), (5, 5), (8, 2)], radii=0.5, shapes=[None, box(1, 0.5), capsule(1.5, 0.3)], box=BOX)
    trajectory = run(world, 0.1)
    loaded = load_trajectory(trajectory.save(tmp_path / "capsules.npz")).world
    assert loaded.polygons[2] == Capsule(1.5, 0.3) and loaded.polygons[0] is None
    for name in ("shapes", "radii", "masses", "inertias", "vertex_start", "body_vertices", "capsule_radii"):
        np.testing.assert_array_equal(getattr(loaded, name), getattr(world, name))


def test_what_does_not_take_a_capsule_says_so():
    world = World([(5, 5)], shapes=[capsule(1.0, 0.5)], box=BOX)
    with pytest.raises(ValueError, match="this scene has capsules: use method discrete"):
        collisim.simulate(Scene(world=world, method="ccd"))
    with pytest.raises(ValueError, match="not both"):
        World([(5, 5)], shapes=[capsule(1.0, 0.5)], polygons=[None], box=BOX)
    with pytest.raises(ValueError, match="capsule length must be a finite number > 0"):
        capsule(0.0, 1.0)
    with pytest.raises(ValueError, match="capsules 0 and 1 overlap|bodies 0 and 1 overlap"):
        collisim.simulate(Scene(world=World([(5, 5), (5.5, 5.2)], shapes=[capsule(2, 0.5)] * 2, box=BOX)))


@pytest.mark.comparison
def test_a_dropped_capsule_rests_where_pymunk_puts_it():
    from collisim.analysis.reference import simulate_pymunk
    from collisim.analysis.reference.pymunk_mirror import Mirror
    import pymunk
    world = World([(5, 3.0)], shapes=[capsule(2.0, 0.5)], angles=0.3, box=BOX, gravity=(0, -G), restitution=0.0,
                  friction=0.5)
    (shape,) = Mirror(world).bodies[0].shapes
    assert isinstance(shape, pymunk.Segment) and shape.radius == 0.5
    assert (shape.a, shape.b) == ((-1.0, 0.0), (1.0, 0.0))
    scene = Scene(world=world, fps=FPS, seconds=3.0)
    ours, theirs = collisim.simulate(scene), simulate_pymunk(scene)
    assert ours.positions[-1, 0, 1] == pytest.approx(theirs.positions[-1, 0, 1], abs=2e-2)
    assert abs(math.remainder(ours.angles[-1, 0] - theirs.angles[-1, 0], math.pi)) < 1e-2


def test_raycast_hits_a_standing_capsules_side_and_cap():
    world = World([(5, 5)], shapes=[capsule(2.0, 0.5)], angles=np.pi / 2, box=BOX)   # core (5, 4)-(5, 6)
    side = collisim.raycast(world, (1, 5), (1, 0))
    assert side.kind == "body" and side.distance == pytest.approx(3.5, abs=1e-12)
    np.testing.assert_allclose(side.normal, [-1.0, 0.0], atol=1e-12)
    top = collisim.raycast(world, (5, 9), (0, -1))
    np.testing.assert_allclose(top.point, [5.0, 6.5], atol=1e-12)
    cap = collisim.raycast(world, (1, 6.2), (1, 0))      # the upper cap's circle, 0.2 above its centre
    half_chord = math.sqrt(0.5 ** 2 - 0.2 ** 2)
    np.testing.assert_allclose(cap.point, [5.0 - half_chord, 6.2], atol=1e-12)
    np.testing.assert_allclose(cap.normal, [-half_chord / 0.5, 0.4], atol=1e-12)


def test_a_capsule_is_drawn_filled_to_its_round_ends():
    from collisim.render import raster
    from collisim.render.view import View
    world = World([(5, 5)], shapes=[capsule(4.0, 1.0)], angles=0.0, colors=[(200, 100, 50)], box=BOX)
    view = View(BOX, (0, 0, 400, 400), margin=0.0)            # 40 pixels a unit, y down
    canvas = np.zeros((400, 400, 3), np.uint8)
    outlines, bodies = raster.polygon_outlines(world, world.positions, world.angles)
    raster.draw_polygons(canvas, [view.to_pixels(o) for o in outlines], world.colors[bodies])
    filled = canvas.any(axis=2)
    def at(x, y):
        column, row = view.to_pixels([x, y])
        return filled[int(row), int(column)]
    assert bodies.tolist() == [0] and at(5, 5) and at(3, 5.9) and at(7, 4.1)   # the middle and the sides
    assert at(7.9, 5.0) and at(2.1, 5.0)                     # the caps' far ends, r beyond the centres
    assert not at(7.8, 5.8) and not at(2.2, 4.2)             # outside the caps' round corners
    assert not at(5, 6.2) and not at(8.2, 5.0)
    # the whole outline: the capsule's area (40² pixels a unit) lies between the pixels fully
    # inside it (its colour at full strength) and every pixel it touches (edge and anti-aliasing)
    full = (canvas[:, :, 2] == 200).sum()
    assert full < 40 ** 2 * world.masses[0] < filled.sum() < 1.05 * 40 ** 2 * world.masses[0]


def test_a_fast_spinning_capsule_stays_in_the_box_and_keeps_its_energy():
    # five of its lengths a frame: the walls' rows, not a polygon's flight at its vertices
    world = World([(5.0, 5.0)], velocities=[(50.0, 13.0)], angular_velocities=[3.0], shapes=[capsule(1.0, 0.2)],
                  box=BOX, restitution=1.0)
    trajectory = run(world, 2.0)
    assert trajectory.wall_collisions.sum() >= 10
    for f in range(len(trajectory.times)):
        centres = world.placed_vertices(trajectory.positions[f], trajectory.angles[f])
        assert centres.min() >= 0.2 - 1e-9 and centres.max() <= 10.0 - 0.2 + 1e-9
    kinetic = trajectory.kinetic_energy()
    assert np.abs(kinetic - kinetic[0]).max() <= 1e-9 * kinetic[0]


def test_the_bounding_volume_funnel_holds_capsules_and_its_exact_level_is_shapely():
    from collisim.engine.hierarchy import hierarchy
    rng = np.random.default_rng(11)
    kinds = [capsule(1.6, 0.4), capsule(0.5, 0.6), box(1.0, 0.6), None]
    world = World([(1.5 + 2.2 * (k % 4), 1.5 + 2.4 * (k // 4)) for k in range(16)], radii=0.5,
                  shapes=[kinds[k % 4] for k in range(16)], box=(0, 0, 10, 10))
    pairs = np.array([(i, j) for i in range(16) for j in range(i + 1, 16)])
    touching_pairs = 0
    for _ in range(20):
        positions = rng.uniform(1.5, 8.5, (16, 2))
        angles = rng.uniform(0, 2 * np.pi, 16)
        placed = world.placed_vertices(positions, angles)
        def shape(i):
            rows = placed[world.vertex_start[i]:world.vertex_start[i + 1]]
            if np.isnan(world.capsule_radii[i]):
                return Polygon(rows) if len(rows) else Point(positions[i]).buffer(0.5, quad_segs=256)
            return LineString(rows).buffer(world.capsule_radii[i], quad_segs=256)
        found = hierarchy(world, positions, angles, pairs=pairs)
        for (i, j), passes in zip(found["pairs"], found["passes"]):
            distance = shape(i).distance(shape(j))
            if distance > 1e-3:
                assert not passes[3]
            elif shape(i).intersection(shape(j)).area > 1e-3:
                assert passes.all()          # every volume holds its shape: none rejects a touching pair
                touching_pairs += 1
    assert touching_pairs > 20
