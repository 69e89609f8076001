"""Bodies against a collision map, under both methods: nothing gets out of a closed level at any
speed, bounces keep energy, the map's collisions are counted and logged, and bad starts are
refused."""
import numpy as np
import pytest
from matplotlib.path import Path as Polygon

import collisim
from collisim.core.kinds import MAP

RADIUS = 0.2
BOX = (0.0, 0.0, 8.0, 8.0)
CELL = 0.05


def star_container() -> np.ndarray:
    """A closed, non-convex free region: a seven-pointed star, inside solid."""
    angles = np.linspace(0.0, 2.0 * np.pi, 14, endpoint=False)
    radii = np.where(np.arange(14) % 2 == 0, 3.7, 2.2)
    return np.column_stack([4.0 + radii * np.cos(angles), 4.0 + radii * np.sin(angles)])


def container_map() -> collisim.CollisionMap:
    height = width = int(BOX[2] / CELL)
    rows, cols = np.mgrid[0:height, 0:width]
    centres = np.column_stack([((cols + 0.5) * CELL).ravel(), ((height - rows - 0.5) * CELL).ravel()])
    free = Polygon(star_container()).contains_points(centres).reshape(height, width)
    return collisim.CollisionMap.from_image(np.where(free, 255, 0).astype(np.uint8), cell=CELL)


@pytest.fixture(scope="module")
def level():
    return container_map()


def fast_world(level, n=12, speed_radii_per_frame=10.0, gravity=(0.0, 0.0), seed=0):
    rng = np.random.default_rng(seed)
    angles = np.linspace(0.0, 2.0 * np.pi, n, endpoint=False)
    positions = 4.0 + 1.1 * np.column_stack([np.cos(angles), np.sin(angles)])
    directions = rng.normal(size=(n, 2))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    velocities = directions * speed_radii_per_frame * RADIUS * 60 * rng.uniform(0.3, 1.0, (n, 1))
    return collisim.World(positions, velocities, RADIUS, box=BOX, map=level, gravity=gravity)


@pytest.mark.parametrize("method", ["discrete", "ccd"])
def test_nothing_leaves_a_closed_map_at_ten_radii_a_frame(level, method):
    frames = 100_000
    world = fast_world(level)
    trajectory = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=frames / 60, method=method))
    centres = trajectory.positions.reshape(-1, 2)
    outside = ~Polygon(star_container()).contains_points(centres)
    assert not outside.any(), f"{outside.sum()} samples outside the level"
    depth = RADIUS - level.distance(centres)
    assert depth.max() < 2 * CELL   # within the map's resolution of the exact outline


def test_elastic_bounces_off_the_map_keep_energy_without_gravity(level):
    world = fast_world(level, speed_radii_per_frame=2.0)
    world = collisim.World(world.positions[:1], world.velocities[:1], RADIUS, box=BOX, map=level)
    trajectory = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=5.0))
    speed = np.linalg.norm(trajectory.velocities[:, 0], axis=1)
    np.testing.assert_allclose(speed, speed[0], rtol=1e-12)
    assert trajectory.segment_collisions.sum() > 10


def test_map_collisions_are_logged_as_map_events_under_both_methods(level):
    world = fast_world(level, n=4, speed_radii_per_frame=3.0)
    for method in ("discrete", "ccd"):
        trajectory = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=2.0, method=method))
        on_map = trajectory.events.kind == MAP
        assert on_map.sum() > 0
        assert trajectory.segment_collisions.sum() >= on_map.sum()
        if method == "ccd":
            assert (trajectory.events.j[on_map] >= 0).all() and (trajectory.events.j[on_map] < len(level.segments)).all()
        # each contact point lies on the outline
        points = trajectory.events.point[on_map]
        assert np.abs(level.distance(points)).max() < 2 * CELL


def test_a_body_in_the_solid_is_refused(level):
    world = collisim.World([[0.5, 0.5]], [[0.0, 0.0]], RADIUS, box=BOX, map=level)
    with pytest.raises(ValueError, match="starts inside the collision map's solid"):
        collisim.simulate(collisim.Scene(world=world, fps=30, seconds=0.1))


def test_a_body_across_the_outline_is_refused(level):
    tip = star_container()[0]   # (7.7, 4.0): the point of the star on the right
    world = collisim.World([tip - [0.05, 0.0]], [[0.0, 0.0]], RADIUS, box=BOX, map=level)
    with pytest.raises(ValueError, match="collision map"):
        collisim.simulate(collisim.Scene(world=world, fps=30, seconds=0.1, method="ccd"))


def test_map_must_be_a_collision_map():
    with pytest.raises(ValueError, match="map must be a collisim.CollisionMap"):
        collisim.World([[1.0, 1.0]], map="level.png")


def test_resting_on_the_map_floor_under_gravity(level):
    """A ball dropped with e = 0 into the star's lowest point comes to rest there: no sinking,
    no jitter."""
    world = collisim.World([[4.0, 4.0]], [[0.0, 0.0]], RADIUS, box=BOX, map=level, gravity=(0.0, -9.8),
                           restitution=0.0)
    trajectory = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=6.0, substeps=2))
    late = trajectory.positions[-60:, 0]
    assert np.ptp(late, axis=0).max() < 1e-3
    assert level.distance(late).min() > RADIUS - 2 * CELL


def test_a_trajectory_file_keeps_its_map(level, tmp_path):
    world = fast_world(level, n=3, speed_radii_per_frame=1.0)
    trajectory = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=0.2))
    loaded = collisim.load_trajectory(trajectory.save(tmp_path / "run.npz"))
    assert loaded.world.map is not None
    for name, value in level.to_arrays().items():
        assert np.array_equal(value, loaded.world.map.to_arrays()[name]), name
    np.testing.assert_array_equal(loaded.positions, trajectory.positions)


def test_the_maps_bench_error_falls_as_cells_get_finer():
    """`collisim bench maps`' level, measured as the bench does: distance and normal errors
    against the exact shapes shrink with resolution."""
    from collisim.analysis.bench import maps
    points = maps.probe_points(1000)
    exact, normals = maps.exact_distance(points)
    errors = []
    for k in (1.0, 4.0):
        m = maps.level_map(k)
        angle = np.degrees(np.arccos(np.clip(np.einsum("pk,pk->p", m.normal(points), normals), -1, 1)))
        errors.append((np.abs(m.distance(points) - exact).mean(), np.median(angle)))
    (coarse_d, coarse_a), (fine_d, fine_a) = errors
    assert fine_d < 0.5 * coarse_d
    assert fine_a < coarse_a


def test_rays_hit_a_real_map_on_its_outline(level):
    """Rays from inside the level stop on the map's exact outline: the first crossing of the
    ray with the chains, found independently by shapely, with kind "map"."""
    from shapely.geometry import LineString, MultiLineString, Point
    outline = MultiLineString([[(x0, y0), (x1, y1)] for x0, y0, x1, y1 in level.segments])
    world = collisim.World(np.empty((0, 2)), np.empty((0, 2)), RADIUS, box=BOX, map=level)
    rng = np.random.default_rng(3)
    origins = 4.0 + rng.uniform(-1.5, 1.5, (200, 2))
    angles = rng.uniform(0.0, 2.0 * np.pi, 200)
    directions = np.column_stack([np.cos(angles), np.sin(angles)])
    hits = collisim.raycast_many(world, origins, directions, 20.0)
    assert (np.array(hits.KIND_NAMES)[hits.kinds] == "map").all()
    for o, d, distance in zip(origins, directions, hits.distance):
        crossing = LineString([o, o + 20.0 * d]).intersection(outline)
        expected = min(Point(o).distance(Point(p)) for p in getattr(crossing, "geoms", [crossing]))
        assert distance == pytest.approx(expected, abs=1e-9)
