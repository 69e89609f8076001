"""`collisim bench maps`: a collision map's accuracy against its resolution.

The slides promise collision maps that are "very fast, very efficient, accuracy based on
resolution of map". This measures that curve. One level is defined exactly (a closed round
container holding a disc, a triangle and a slanted bar); it is rasterized at several
resolutions, from half a cell to sixteen cells per particle radius, and each map is measured
against the exact shapes:

* distance error: |map.distance - exact distance| at random points near the walls;
* normal error: the angle between map.normal and the exact normal there (mean and 95th
  percentile: on the medial axis between two walls the normal flips, whatever the map);
* penetration: the deepest any body sinks into the exact shapes over a second of the discrete
  method with the map (particles falling and bouncing, 4 substeps a frame);
* position error after 1 s: slower particles (a few bounces in the second, so chaos does not
  swamp the map's error), each alone, under the discrete method with the map against ccd with
  the exact outline (ccd is exact; the discrete steps add their own error, the floor the
  curve flattens onto);
* cost: time per body per step of the map phase, from the discrete run's profile;
* the painted slope: a frictionless, inelastic ball released on a 20-degree slope painted at the
  map's resolution, under each method: its acceleration down the slope after landing (fitted
  over 2 s) against g sin 20°, and the map collisions a second logged while it slides (it should
  log none: it slides, it does not hit).

Lengths are in particle radii. Everything runs in one process, one resolution after another.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

import collisim
from collisim.core.files import save_figure, write_table
from collisim.core.kinds import MAP
from collisim.statics.collision_map import CollisionMap

RADIUS = 0.2
BOX = (0.0, 0.0, 16.0, 16.0)
CELLS_PER_RADIUS = (0.5, 1.0, 2.0, 4.0, 8.0, 16.0)
CONTAINER = (8.0, 8.0, 7.5)   # cx, cy, r: the free inside of a round container
ROUND = 256                   # sides of the polygons standing in for circles (error 8e-5 r)


def _circle(cx, cy, r, sides=ROUND, clockwise=False) -> np.ndarray:
    angles = np.linspace(0.0, 2.0 * np.pi, sides, endpoint=False)
    if clockwise:
        angles = angles[::-1]
    return np.column_stack([cx + r * np.cos(angles), cy + r * np.sin(angles)])


def level_polygons() -> list:
    """The solid obstacles inside the container, as (k, 2) vertex arrays."""
    return [_circle(5.5, 9.0, 1.6),
            np.array([[9.0, 4.0], [12.5, 4.5], [10.5, 7.0]]),
            np.array([[9.0, 10.8], [13.2, 12.6], [12.9, 13.2], [8.7, 11.4]])]


def exact_segments() -> np.ndarray:
    """(m, 4) the level's exact outline: the container's rim and every obstacle's edges."""
    loops = [_circle(*CONTAINER)] + level_polygons()
    rows = [np.column_stack([loop, np.roll(loop, -1, axis=0)]) for loop in loops]
    return np.concatenate(rows)


def exact_distance(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Signed distance (m,) from points (m, 2) to the exact level (negative in solid) and the
    unit normal (m, 2) toward free space."""
    seg = exact_segments()
    a, b = seg[:, :2], seg[:, 2:]
    ab = b - a
    t = np.clip(np.einsum("pmk,mk->pm", points[:, None, :] - a[None], ab) / np.einsum("mk,mk->m", ab, ab), 0, 1)
    closest = a[None] + t[..., None] * ab[None]
    gaps = np.linalg.norm(points[:, None, :] - closest, axis=2)
    nearest = np.argmin(gaps, axis=1)
    rows = np.arange(len(points))
    away = points - closest[rows, nearest]
    distance = gaps[rows, nearest]
    solid = _in_solid(points)
    normal = away / np.maximum(distance, 1e-300)[:, None]
    return np.where(solid, -distance, distance), np.where(solid[:, None], -normal, normal)


def _in_solid(points: np.ndarray) -> np.ndarray:
    from matplotlib.path import Path as Polygon
    cx, cy, r = CONTAINER
    solid = np.hypot(points[:, 0] - cx, points[:, 1] - cy) > r
    for polygon in level_polygons():
        solid |= Polygon(polygon).contains_points(points)
    return solid


def level_map(cells_per_radius: float) -> CollisionMap:
    """The level as a bitmap with `cells_per_radius` pixels per particle radius, each pixel
    solid where its centre lies in the exact solid, made into a map."""
    cell = RADIUS / cells_per_radius
    height, width = int(np.ceil(BOX[3] / cell)), int(np.ceil(BOX[2] / cell))
    rows, cols = np.mgrid[0:height, 0:width]
    centres = np.column_stack([((cols + 0.5) * cell).ravel(), ((height - rows - 0.5) * cell).ravel()])
    image = np.where(_in_solid(centres), 0, 255).astype(np.uint8).reshape(height, width)
    return CollisionMap.from_image(image, cell=cell, origin=(0.0, 0.0))


def probe_points(count: int = 4000, seed: int = 1) -> np.ndarray:
    """Random points in free space within 2 radii of a wall: where contacts happen."""
    rng = np.random.default_rng(seed)
    points = rng.uniform(BOX[:2], BOX[2:], (count * 20, 2))
    d, _ = exact_distance(points)
    keep = points[(d > 0.0) & (d < 2 * RADIUS)]
    return keep[:count]


def drop_world(count: int = 40, seed: int = 2, collision_map=None, segments=None,
               speed: float = 4 * RADIUS * 60 / 2) -> collisim.World:
    """`count` particles in free space of the level, under gravity, elastic, with velocities
    normal with deviation `speed` per axis (by default about 4 radii a frame at 60 fps at the
    fastest: a test of tunnelling)."""
    rng = np.random.default_rng(seed)
    chosen = []
    while len(chosen) < count:
        p = rng.uniform(BOX[:2], BOX[2:], 2)
        if exact_distance(p[None])[0][0] > 2.5 * RADIUS and all(np.hypot(*(p - q)) > 2.2 * RADIUS for q in chosen):
            chosen.append(p)
    velocities = rng.normal(0.0, 1.0, (count, 2)) * speed
    return collisim.World(np.array(chosen), velocities, RADIUS, box=BOX, gravity=(0.0, -9.8),
                          map=collision_map, segments=segments)


SLOPE = math.radians(20.0)
SLOPE_BOX = (0.0, 0.0, 16.0, 10.0)
LANDED = 0.25   # seconds: the ball starts a pixel above the slope


def _slope_height(x):
    return 8.0 - math.tan(SLOPE) * x


def slope_world(cells_per_radius: float) -> collisim.World:
    """A ball at rest a pixel above a 20-degree slope painted with cells_per_radius pixels a
    radius (a pixel solid where its centre lies under the line), frictionless and inelastic."""
    cell = RADIUS / cells_per_radius
    width, height = int(round(SLOPE_BOX[2] / cell)), int(round(SLOPE_BOX[3] / cell))
    columns, rows = np.meshgrid(np.arange(width), np.arange(height))
    below = SLOPE_BOX[3] - (rows + 0.5) * cell < _slope_height((columns + 0.5) * cell)
    level = CollisionMap.from_image(np.where(below, 0, 255).astype(np.uint8), cell=cell)
    normal = np.array([math.sin(SLOPE), math.cos(SLOPE)])
    start = np.array([1.5, _slope_height(1.5)]) + (RADIUS + cell) * normal
    return collisim.World([start], [[0.0, 0.0]], RADIUS, box=SLOPE_BOX, map=level, gravity=(0.0, -9.8),
                          restitution=0.0)


def slope_slide(cells_per_radius: float, method: str, seconds: float = 2.0) -> tuple:
    """(the relative error of the acceleration down the painted slope, map collisions a second
    while it slides), after landing."""
    run = collisim.simulate(collisim.Scene(world=slope_world(cells_per_radius), fps=60, seconds=seconds,
                                           method=method))
    down = run.positions[:, 0] @ np.array([math.cos(SLOPE), -math.sin(SLOPE)])
    landed = run.times > LANDED
    acceleration = 2.0 * np.polyfit(run.times[landed], down[landed], 2)[0]
    sliding = (run.events.kind == MAP) & (run.events.time > LANDED)
    return acceleration / (9.8 * math.sin(SLOPE)) - 1.0, float(sliding.sum() / (seconds - LANDED))


def measure(cells_per_radius: float, seconds: float = 1.0) -> dict:
    m = level_map(cells_per_radius)
    points = probe_points()
    d_exact, n_exact = exact_distance(points)
    distance_error = np.abs(m.distance(points) - d_exact) / RADIUS
    cosine = np.clip(np.einsum("pk,pk->p", m.normal(points), n_exact), -1.0, 1.0)
    angle = np.degrees(np.arccos(cosine))

    world = drop_world(collision_map=m)
    run = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=seconds, substeps=4, broadphase="brute"))
    depths = RADIUS - exact_distance(run.positions.reshape(-1, 2))[0]
    statics_seconds = run.profile.get("statics", float("nan"))
    steps = (len(run.times) - 1) * 4

    # a few bounces in the second, so the difference measures the map, not chaos
    slow = drop_world(count=20, seed=4, collision_map=m, speed=2.0)
    errors = []
    for i in range(slow.n):
        alone = collisim.World(slow.positions[i:i + 1], slow.velocities[i:i + 1], RADIUS, box=BOX,
                               gravity=slow.gravity, map=m)
        discrete = collisim.simulate(collisim.Scene(world=alone, fps=60, seconds=seconds, substeps=4))
        exact = collisim.simulate(collisim.Scene(world=alone.copy(map=None, segments=exact_segments()),
                                                 fps=60, seconds=seconds, method="ccd"))
        errors.append(np.hypot(*(discrete.positions[-1, 0] - exact.positions[-1, 0])) / RADIUS)
    slope = {method: slope_slide(cells_per_radius, method) for method in ("discrete", "ccd")}
    return {"cells_per_radius": cells_per_radius, "cell": m.cell, "pixels": int(m.solid.size),
            "distance_error_mean": float(distance_error.mean()), "distance_error_max": float(distance_error.max()),
            "normal_error_deg_mean": float(angle.mean()), "normal_error_deg_p95": float(np.percentile(angle, 95)),
            "penetration_max": float(max(depths.max(), 0.0) / RADIUS),
            "position_error_1s_median": float(np.median(errors)),
            "map_ns_per_body_step": float(1e9 * statics_seconds / steps / world.n),
            "slope_error_discrete": slope["discrete"][0], "slope_error_ccd": slope["ccd"][0],
            "slope_collisions_per_s_discrete": slope["discrete"][1], "slope_collisions_per_s_ccd": slope["ccd"][1]}


def run(out_dir: Path, cells=CELLS_PER_RADIUS, seconds: float = 1.0, progress: bool = True) -> dict:
    """Measure every resolution; write maps.csv and maps.png into out_dir; return the rows."""
    rows = []
    for k in cells:
        rows.append(measure(k, seconds))
        if progress:
            print(format_row(rows[-1]), flush=True)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    csv_path = out_dir / "maps.csv"
    write_table(csv_path, rows, list(rows[0]))
    png_path = chart(rows, out_dir / "maps.png")
    return {"rows": rows, "csv": str(csv_path), "png": str(png_path)}


HEADER = ("cells/r  dist err mean/max (r)  normal err mean/p95 (deg)  penetration (r)  position err 1 s (r)  "
          "ns/body/step  slope accel err discrete/ccd  slope collisions/s discrete/ccd")


def format_row(r: dict) -> str:
    return (f"{r['cells_per_radius']:7.1f}  {r['distance_error_mean']:9.4f} / {r['distance_error_max']:7.4f}  "
            f"{r['normal_error_deg_mean']:11.2f} / {r['normal_error_deg_p95']:7.2f}  "
            f"{r['penetration_max']:15.4f}  {r['position_error_1s_median']:20.4f}  {r['map_ns_per_body_step']:12.0f}  "
            f"{100 * r['slope_error_discrete']:+12.2f} % / {100 * r['slope_error_ccd']:+6.2f} %  "
            f"{r['slope_collisions_per_s_discrete']:14.1f} / {r['slope_collisions_per_s_ccd']:5.1f}")


def chart(rows: list, path: Path) -> Path:
    """Errors in radii against cells per radius (log-log; a penetration of 0 is left off the
    log axis and marked at the bottom), the normal error in degrees beside it, and the painted
    slope's acceleration error under each method (log-log, the 2 % target marked)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    k = np.array([r["cells_per_radius"] for r in rows])
    fig, (left, right, slope) = plt.subplots(1, 3, figsize=(15, 4.2), dpi=120)
    for key, label in (("distance_error_mean", "distance error, mean"), ("distance_error_max", "distance error, max"),
                       ("penetration_max", "deepest penetration"),
                       ("position_error_1s_median", "position error after 1 s, median")):
        values = np.array([r[key] for r in rows])
        line, = left.loglog(k[values > 0], values[values > 0], marker="o", label=label)
        if (values <= 0).any():
            left.plot(k[values <= 0], np.full((values <= 0).sum(), left.get_ylim()[0]), "v", color=line.get_color(),
                      clip_on=False, label=f"{label}: 0")
    left.set_xlabel("map cells per particle radius")
    left.set_ylabel("particle radii")
    left.set_title("errors against the exact level")
    left.legend(fontsize=7)
    for key, label in (("normal_error_deg_mean", "mean"), ("normal_error_deg_p95", "95th percentile")):
        right.semilogx(k, [r[key] for r in rows], marker="s", label=label)
    right.set_xlabel("map cells per particle radius")
    right.set_ylabel("degrees")
    right.set_title("normal error within 2 radii of a wall")
    right.legend(fontsize=7)
    for method, marker in (("discrete", "o"), ("ccd", "s")):
        errors = np.abs([r[f"slope_error_{method}"] for r in rows])
        slope.loglog(k, np.maximum(errors, 1e-5), marker=marker, label=method)
    slope.axhline(0.02, color="grey", linestyle="--", linewidth=1, label="2 %")
    slope.set_xlabel("map cells per particle radius")
    slope.set_ylabel("|acceleration / g sin 20° - 1|")
    slope.set_title("a frictionless ball on a painted 20° slope")
    slope.legend(fontsize=7)
    fig.suptitle("Collision map accuracy against resolution")
    fig.tight_layout()
    save_figure(fig, path)
    plt.close(fig)
    return path
