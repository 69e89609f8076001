"""The slides' hierarchy of bounding volumes (narrowphase/hierarchy.py): each level against an
independent reference on thousands of random pairs, touching and degenerate ones included
(bounding circles and boxes against numpy, oriented boxes against shapely's minimum rotated
rectangle and polygon intersection, the exact level against shapely's polygons and distances);
no level ever rejects a pair whose shapes touch; the funnel's counts on random worlds and on the
two polygon scenes, recorded by the engine into every frame and kept by the trajectory file."""
import numpy as np
import pytest
import shapely
from shapely.geometry import Point, Polygon

import collisim
from collisim.model.trajectory import LEVELS, NOT_COUNTED, load_trajectory
from collisim.engine.hierarchy import (CX, CY, HALF_H, HALF_W, SLACK, UX, UY, false_positive_rates,
                                            hierarchy, volumes_of)
from collisim.render.hud import volume_line
from collisim.shapes import box, regular
from conftest import decode_video

CLEAR = 1e-9   # a reference's margin below which a pair counts as touching (the volumes' slack)


def random_shapes(rng, n):
    """n bodies: random convex polygons (hulls of gaussian points, some long and thin), boxes,
    triangles, hexagons and circles (None)."""
    from scipy.spatial import ConvexHull
    shapes = []
    for k in range(n):
        kind = k % 5
        if kind == 0:
            points = rng.normal(0.0, 1.0, (8, 2)) * rng.uniform(0.2, 1.0, 2)
            shapes.append(points[ConvexHull(points).vertices])
        else:
            shapes.append([box(rng.uniform(0.2, 2.0), rng.uniform(0.1, 0.6)), regular(3, rng.uniform(0.3, 0.9)),
                           regular(6, rng.uniform(0.3, 0.8)), None][kind - 1])
    return shapes


def random_world(rng, n=80):
    """A world of n random bodies, set apart on a grid (a World may not start overlapping);
    the tests move them with positions= and angles=."""
    side = int(np.ceil(np.sqrt(n)))
    grid = 5.0 * np.column_stack([np.arange(n) % side, np.arange(n) // side]) + 3.0
    return collisim.World(grid, radii=rng.uniform(0.1, 0.8, n), polygons=random_shapes(rng, n),
                          box=(0.0, 0.0, 5.0 * side + 6, 5.0 * side + 6))


def crowded(rng, world, spread=4.0):
    """Positions (n, 2) packed into a small square, and random angles: most pairs' bounding
    circles overlap, many shapes do."""
    return rng.uniform(0.0, spread, (world.n, 2)), rng.uniform(0.0, 2 * np.pi, world.n)


def all_pairs(n):
    return np.column_stack(np.triu_indices(n, 1))


def outlines(world, positions, angles):
    """Each body's shapely shape: its polygon, or a circle as (centre, radius)."""
    vertices = world.placed_vertices(positions, angles)
    shapes = []
    for i in range(world.n):
        s, e = world.vertex_start[i], world.vertex_start[i + 1]
        shapes.append(Polygon(vertices[s:e]) if e > s else (positions[i], world.radii[i]))
    return shapes


def exact_reference(a, b):
    """(gap, overlap): the distance between two shapes (0 when they meet) and how deep they
    overlap (area, or for circles the depth), from shapely and numpy."""
    if isinstance(a, tuple) and isinstance(b, tuple):
        d = np.hypot(*(a[0] - b[0])) - a[1] - b[1]
        return max(d, 0.0), max(-d, 0.0)
    if isinstance(a, tuple) or isinstance(b, tuple):
        (centre, r), polygon = (a, b) if isinstance(a, tuple) else (b, a)
        d = polygon.distance(Point(centre)) - r
        inside = polygon.contains(Point(centre))
        return max(d, 0.0), (1.0 if inside else max(-d, 0.0))
    return a.distance(b), a.intersection(b).area


def rectangle(volumes, i):
    ux, uy, w, h = volumes[i, UX], volumes[i, UY], volumes[i, HALF_W], volumes[i, HALF_H]
    corners = [(volumes[i, CX] + s * w * ux - t * h * uy, volumes[i, CY] + s * w * uy + t * h * ux)
               for s, t in ((1, 1), (-1, 1), (-1, -1), (1, -1))]
    return Polygon(corners)


@pytest.fixture(scope="module")
def random_cases():
    """Three crowded states of an 80-body world: 9 480 pairs, with every level tested on its own."""
    rng = np.random.default_rng(20261123)
    world = random_world(rng)
    cases = []
    for spread in (3.0, 6.0, 12.0):
        positions, angles = crowded(rng, world, spread)
        found = hierarchy(world, positions, angles, pairs=all_pairs(world.n))
        cases.append((world, positions, angles, found))
    return cases


def test_bounding_circles_and_boxes_agree_with_numpy(random_cases):
    checked = 0
    for world, positions, angles, found in random_cases:
        i, j = found["pairs"].T
        gap = np.hypot(*(positions[i] - positions[j]).T) - world.radii[i] - world.radii[j]
        clear = np.abs(gap) > CLEAR * (world.radii[i] + world.radii[j])
        assert np.array_equal(found["passes"][clear, 0], gap[clear] <= 0)
        lo, hi = _boxes(world, positions, angles)
        apart = np.maximum(lo[j] - hi[i], lo[i] - hi[j]).max(axis=1)   # > 0: apart on some axis
        clear = np.abs(apart) > CLEAR * (world.radii[i] + world.radii[j])
        assert np.array_equal(found["passes"][clear, 1], apart[clear] <= 0)
        checked += clear.sum()
    assert checked > 9000


def _boxes(world, positions, angles):
    """Each body's axis-aligned box from numpy: its placed vertices' extremes, or centre ± r."""
    vertices = world.placed_vertices(positions, angles)
    lo, hi = positions - world.radii[:, None], positions + world.radii[:, None]
    for i in np.flatnonzero(world.shapes != 0):
        s, e = world.vertex_start[i], world.vertex_start[i + 1]
        lo[i], hi[i] = vertices[s:e].min(axis=0), vertices[s:e].max(axis=0)
    return lo, hi


def test_oriented_boxes_are_the_minimum_rectangles_and_overlap_as_shapely_says(random_cases):
    world, positions, angles, found = random_cases[0]
    _, volumes = volumes_of(world, positions, angles)
    shapes = outlines(world, positions, angles)
    rectangles = [rectangle(volumes, i) for i in range(world.n)]
    for i in np.flatnonzero(world.shapes != 0):   # the oriented box holds the shape and is the smallest
        grow = SLACK * world.radii[i]
        tight = 4.0 * (volumes[i, HALF_W] - grow) * (volumes[i, HALF_H] - grow)
        assert tight == pytest.approx(shapely.oriented_envelope(shapes[i]).area, rel=1e-9)
        assert rectangles[i].buffer(1e-9).covers(shapes[i])
    for i in np.flatnonzero(world.shapes == 0):   # a circle's is its box, the square around it
        square = Point(positions[i]).buffer(world.radii[i], cap_style="square")
        assert rectangles[i].symmetric_difference(square).area < 1e-8 * square.area
    checked = 0
    for case in random_cases:
        world, positions, angles, found = case
        _, volumes = volumes_of(world, positions, angles)
        rectangles = [rectangle(volumes, i) for i in range(world.n)]
        for (i, j), alone in zip(found["pairs"], found["passes"][:, 2]):
            gap, overlap = rectangles[i].distance(rectangles[j]), rectangles[i].intersection(rectangles[j]).area
            if gap > CLEAR or overlap > CLEAR:
                assert alone == (gap == 0.0), (i, j, gap, overlap)
                checked += 1
    assert checked > 9000


def test_the_exact_level_agrees_with_shapely(random_cases):
    checked = touching = 0
    for world, positions, angles, found in random_cases:
        shapes = outlines(world, positions, angles)
        for (i, j), alone in zip(found["pairs"], found["passes"][:, 3]):
            gap, overlap = exact_reference(shapes[i], shapes[j])
            if gap > CLEAR or overlap > CLEAR:
                assert alone == (gap == 0.0), (i, j, gap, overlap)
                checked += 1
                touching += alone
    assert checked > 9000 and touching > 500


def test_no_level_rejects_a_pair_that_touches_and_the_funnel_stops_at_the_first_miss(random_cases):
    for world, positions, angles, found in random_cases:
        passes, levels = found["passes"], found["levels"]
        assert passes[passes[:, 3]].all()
        assert np.array_equal(levels, np.cumprod(passes, axis=1).sum(axis=1))
        counts = found["counts"]
        assert (np.diff(counts) <= 0).all() and counts[0] > counts[3] > 0
        assert counts[3] == passes[:, 3].sum()     # the funnel finds every touching pair


def test_the_default_pairs_miss_no_pair_whose_bounding_circles_overlap(random_cases):
    for world, positions, angles, found in random_cases:
        default = hierarchy(world, positions, angles)
        assert np.array_equal(default["counts"], found["counts"])


# shapes placed to touch exactly (a face on a face, corner on corner, a ball on a face, balls
# tangent) and degenerate ones (the same centre, one inside the other), in exact binary arithmetic
TOUCHING = {
    "faces": ([box(1, 1), box(1, 1)], [(0.0, 0.0), (1.0, 0.0)], [0.0, 0.0]),
    "corners": ([box(1, 1), box(1, 1)], [(0.0, 0.0), (1.0, 1.0)], [0.0, 0.0]),
    "face and half face": ([box(2, 1), box(1, 1)], [(0.0, 0.0), (0.5, 1.0)], [0.0, 0.0]),
    "ball on a face": ([box(1, 1), None], [(0.0, 0.0), (1.0, 0.0)], [0.0, 0.0]),
    "ball on a corner": ([box(2, 2), None], [(0.0, 0.0), (1.375, 1.5)], [0.0, 0.0]),   # 3-4-5: 0.375, 0.5 → 0.625
    "balls": ([None, None], [(0.0, 0.0), (1.0, 0.0)], [0.0, 0.0]),
    "same centre": ([box(2, 0.25), None], [(0.0, 0.0), (0.0, 0.0)], [0.7, 0.0]),
    "inside": ([regular(6, 2.0), box(0.5, 0.5)], [(0.0, 0.0), (0.25, -0.5)], [0.0, 1.0]),
}
RADII = {"ball on a corner": 0.625}


@pytest.mark.parametrize("case", sorted(TOUCHING))
def test_touching_and_degenerate_pairs_pass_every_level(case):
    polygons, placed, angles = TOUCHING[case]
    world = collisim.World([(0.0, 0.0), (50.0, 0.0)], radii=RADII.get(case, 0.5), polygons=polygons,
                           box=(-10.0, -10.0, 60.0, 10.0))
    found = hierarchy(world, np.array(placed), np.array(angles), pairs=[(0, 1)])
    assert found["passes"].all() and found["levels"][0] == 4
    assert list(found["counts"]) == [1, 1, 1, 1]


def test_each_level_catches_what_the_coarser_one_let_through():
    """A plank and a ball beside its end: circles overlap, boxes do not. A turned plank: boxes
    overlap, oriented boxes do not. A triangle's corner region: oriented boxes overlap, shapes not."""
    plank, ball = box(4.0, 0.2), None
    cases = [([plank, ball], [(0.0, 0.0), (0.0, 1.0)], [0.0, 0.0], 1),
             ([plank, ball], [(0.0, 0.0), (1.2, -1.2)], [np.pi / 4, 0.0], 2),
             ([regular(3, 1.0), ball], [(0.0, 0.0), (0.9, 0.7)], [0.0, 0.0], 3)]
    for polygons, placed, angles, level in cases:
        world = collisim.World([(0.0, 0.0), (50.0, 0.0)], radii=0.3, polygons=polygons, box=(-10.0, -10.0, 60.0, 10.0))
        found = hierarchy(world, np.array(placed), np.array(angles), pairs=[(0, 1)])
        assert found["levels"][0] == level, (placed, found["passes"])


# --- the engine's counts ---------------------------------------------------------------------------

@pytest.fixture(scope="module")
def scene_runs():
    """The two polygon scenes run by the engine: bounding_volumes whole, polygons' first 2 s."""
    return {name: collisim.simulate(collisim.load_scene(name).replace(seconds=seconds))
            for name, seconds in (("bounding_volumes", 10.0), ("polygons", 2.0))}


@pytest.mark.parametrize("name", ["bounding_volumes", "polygons"])
def test_every_frame_records_the_funnel_of_its_own_state(scene_runs, name):
    trajectory = scene_runs[name]
    counts = trajectory.hierarchy
    assert counts.shape == (len(trajectory.times), len(LEVELS)) and (counts >= 0).all()
    assert (np.diff(counts, axis=1) <= 0).all()          # each level passes no more than the one before
    world = trajectory.world
    for f in range(0, len(counts), 7):                    # the engine's broad phase, recounted with the grid
        found = hierarchy(world, trajectory.positions[f], trajectory.angles[f])
        assert np.array_equal(counts[f], found["counts"]), f


def test_the_bounding_volumes_scene_shows_false_positives_at_every_level(scene_runs):
    """Its shapes drift elastically: a pair meets at a speculative contact and parts within the
    step, so none touch at a frame, and every pair a volume lets through is a false positive;
    each tighter volume lets fewer through. In the polygons scene's pile, shapes do touch, and
    the false-positive rate falls at every level."""
    totals = scene_runs["bounding_volumes"].hierarchy.sum(axis=0)
    assert totals[0] > totals[1] > totals[2] > 0 and totals[3] == 0
    pile = scene_runs["polygons"].hierarchy
    rates = false_positive_rates(pile)
    assert pile[:, 3].sum() > 0                          # shapes do touch
    assert 1.0 > rates[0] > rates[1] > rates[2] > rates[3] == 0.0
    assert (pile[:, 2] > pile[:, 3]).any()               # some pairs' oriented boxes overlap, shapes apart


def test_the_counts_survive_the_trajectory_file(scene_runs, tmp_path):
    trajectory = scene_runs["bounding_volumes"]
    loaded = load_trajectory(trajectory.save(tmp_path / "run.npz"))
    assert np.array_equal(loaded.hierarchy, trajectory.hierarchy)
    with np.load(tmp_path / "run.npz") as data:          # a file from before the counts
        arrays = {key: data[key] for key in data.files if key != "frame_hierarchy"}
    np.savez(tmp_path / "old.npz", **arrays)
    old = load_trajectory(tmp_path / "old.npz")
    assert old.hierarchy.shape == trajectory.hierarchy.shape and (old.hierarchy == NOT_COUNTED).all()


def test_worlds_of_circles_are_not_counted_and_the_hud_says_why():
    trajectory = collisim.simulate(collisim.load_scene("two_bodies").replace(seconds=0.5))
    assert (trajectory.hierarchy == NOT_COUNTED).all()
    state = type("State", (), {"hierarchy": trajectory.hierarchy[3]})
    assert volume_line(trajectory, state) == ["volumes: circles, each level exact"]
    counted = type("State", (), {"hierarchy": np.array([5, 3, 2, 1])})
    assert volume_line(trajectory, counted) == ["volumes: 5 circles > 3 boxes > 2 oriented > 1 touch"]


def test_false_positive_rates_leave_out_frames_not_counted():
    counts = np.array([[4, 2, 1, 1], [NOT_COUNTED] * 4, [6, 2, 1, 1]])
    assert np.allclose(false_positive_rates(counts), [0.8, 0.5, 0.0, 0.0])


def test_the_scene_renders(tmp_path):
    scene = collisim.load_scene("bounding_volumes").with_options(seconds=0.5)
    out = collisim.render(scene, tmp_path / "volumes.mp4", size=(640, 360), fps=10)
    count, width, height, *_ = decode_video(out)
    assert (count, width, height) == (5, 640, 360)
