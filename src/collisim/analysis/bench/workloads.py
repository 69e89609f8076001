"""The accuracy benchmark's workloads: four seeded scenes that stress a collision method differently.

Every workload is a function returning a `collisim.Scene` (fps 60, 10 s, elastic, box walls,
method "discrete" with the grid broad phase; the benchmark overrides the method). Lengths are
in particle radii: every particle has radius 1, so "radii per frame" is speed / fps and a
position error in radii is a distance in world units. Equal radii keep those units exact;
masses follow area as in any World (all equal here).

* slow_gas(packing=0.05): 250 particles moving 0.2 radii per frame, about one collision per
  particle per second: a step moves a particle a fifth of its radius, the regime where a plain
  discrete step should already be good.
* dense_gas(): the same gas at packing 0.3 (exactly: the box is sized for it), about one
  collision per particle every five frames: clusters of simultaneous contacts, and the
  event-driven method's busiest case.
* fast_gas(): packing 0.05 again at 2 radii per frame: a step carries a particle a whole
  diameter, so discrete detection tunnels through pairs and finds walls late and deep.
* gravity_bounce(): 12 particles bouncing on the floor of a low box under gravity: the
  integrator and the wall response matter more than pair handling.

Initial states are jittered lattices (as scenes/particles_250.py): each particle keeps a gap
to its cell's edge, so no two circles touch at t = 0 whatever the seed.
"""
from __future__ import annotations

import numpy as np

from ...model.scene import Scene
from ...model.world import World

N = 250
RADIUS = 1.0
FPS = 60.0
SECONDS = 10.0
SEED = 2024
GAP = 0.02            # smallest distance (in radii) kept between a circle and its lattice cell's edge
SPEED_SPREAD = 0.5    # speeds are uniform in mean · (1 ± SPEED_SPREAD)

SLOW_RADII_PER_FRAME = 0.2
FAST_RADII_PER_FRAME = 2.0
SPARSE_PACKING = 0.05
DENSE_PACKING = 0.3

DROPS = 12                     # gravity_bounce: particles side by side in a low box
DROP_BOX = (0.0, 0.0, 40.0, 10.0)
DROP_TOP = 7.0                 # highest starting centre
DROP_GRAVITY = 300.0           # radii / s²: bounces a few radii high last a few tenths of a second
DROP_DRIFT = 3.0               # largest sideways speed, radii / s
DROP_THROW = 10.0              # largest initial vertical speed, up or down, radii / s


def square_box(n: int, radius: float, packing: float) -> tuple:
    """(0, 0, side, side) with the n circles covering `packing` of its area."""
    side = float(np.sqrt(n * np.pi * radius ** 2 / packing))
    return 0.0, 0.0, side, side


def packing_fraction(world: World) -> float:
    """The share of the box's area covered by the circles (they never overlap at t = 0)."""
    xmin, ymin, xmax, ymax = world.box
    return float(np.sum(np.pi * world.radii ** 2) / ((xmax - xmin) * (ymax - ymin)))


def mean_radii_per_frame(scene: Scene) -> float:
    """Mean distance travelled per frame at t = 0, in radii."""
    world = scene.world
    return float(np.mean(np.linalg.norm(world.velocities, axis=1) / world.radii) / scene.fps)


def jittered_lattice(n: int, box, radius: float, rng) -> np.ndarray:
    """(n, 2) centres, one per cell of a square lattice filling the box, each moved at random
    within its cell as far as it can go while keeping GAP to the cell's edge."""
    xmin, ymin, xmax, ymax = box
    columns = int(np.ceil(np.sqrt(n * (xmax - xmin) / (ymax - ymin))))
    rows = int(np.ceil(n / columns))
    pitch = min((xmax - xmin) / columns, (ymax - ymin) / rows)
    room = pitch / 2 - radius - GAP
    if room < 0:
        raise ValueError(f"{n} circles of radius {radius:g} do not fit a lattice in box {tuple(box)}")
    column, row = np.divmod(np.arange(n), rows)
    centres = np.column_stack([xmin + (column + 0.5) * pitch, ymin + (row + 0.5) * pitch])
    return centres + rng.uniform(-room, room, (n, 2))


def random_velocities(n: int, mean_speed: float, rng) -> np.ndarray:
    """(n, 2) velocities in uniformly random directions, speeds uniform around mean_speed."""
    angle = rng.uniform(0.0, 2.0 * np.pi, n)
    speed = mean_speed * rng.uniform(1.0 - SPEED_SPREAD, 1.0 + SPEED_SPREAD, n)
    return np.column_stack([np.cos(angle), np.sin(angle)]) * speed[:, None]


def gas(packing: float, speed: float, name: str, n: int = N, seed: int = SEED) -> Scene:
    """n equal circles on a jittered lattice in a square box at this packing, moving on average
    `speed` radii per frame in random directions."""
    rng = np.random.default_rng(seed)
    box = square_box(n, RADIUS, packing)
    positions = jittered_lattice(n, box, RADIUS, rng)
    velocities = random_velocities(n, speed * RADIUS * FPS, rng)
    world = World(positions, velocities, RADIUS, box=box, restitution=1.0)
    return _scene(world, name, f"{n} particles, packing {packing:g}, {speed:g} radii per frame")


# The keyword arguments (defaults: the benchmark's settings) let `collisim sweep` vary them.

def slow_gas(packing: float = SPARSE_PACKING, n: int = N, seed: int = SEED,
             speed: float = SLOW_RADII_PER_FRAME) -> Scene:
    """Sparse slow gas: 250 particles moving ~0.2 radii per frame."""
    return gas(packing, speed, "slow_gas", n, seed)


def dense_gas(packing: float = DENSE_PACKING, n: int = N, seed: int = SEED,
              speed: float = SLOW_RADII_PER_FRAME) -> Scene:
    """Dense gas: packing fraction 0.3, ~0.2 radii per frame."""
    return gas(packing, speed, "dense_gas", n, seed)


def fast_gas(packing: float = SPARSE_PACKING, n: int = N, seed: int = SEED,
             speed: float = FAST_RADII_PER_FRAME) -> Scene:
    """Fast sparse gas: packing 0.05, ~2 radii per frame."""
    return gas(packing, speed, "fast_gas", n, seed)


def gravity_bounce(count: int = DROPS, seed: int = SEED) -> Scene:
    """`count` particles side by side in a low box under strong gravity, released at random
    heights with random vertical speeds and drifting sideways slowly: they bounce on the floor
    a few times a second (about 1 radius per frame at impact) and now and then off each other.
    The bounces are short so that every particle has bounced by 0.25 s, where the benchmark
    compares positions: a drop from mid-height in a tall box would compare free flight only."""
    rng = np.random.default_rng(seed)
    xmin, ymin, xmax, _ = DROP_BOX
    pitch = (xmax - xmin) / count        # one column each: no overlaps at t = 0
    x = xmin + (np.arange(count) + 0.5) * pitch
    y = rng.uniform(ymin + RADIUS + GAP, DROP_TOP, count)
    velocities = np.column_stack([rng.uniform(-DROP_DRIFT, DROP_DRIFT, count),
                                  rng.uniform(-DROP_THROW, DROP_THROW, count)])
    world = World(np.column_stack([x, y]), velocities, RADIUS, box=DROP_BOX, gravity=(0.0, -DROP_GRAVITY),
                  restitution=1.0)
    return _scene(world, "gravity_bounce", f"{count} particles bouncing under g = {DROP_GRAVITY:g}")


def _scene(world: World, name: str, description: str) -> Scene:
    return Scene(world=world, fps=FPS, seconds=SECONDS, method="discrete", broadphase="grid",
                 name=name, description=description)


WORKLOADS = {"slow_gas": slow_gas, "dense_gas": dense_gas, "fast_gas": fast_gas, "gravity_bounce": gravity_bounce}


# --- the gas of `collisim bench broadphase`'s whole steps ------------------------------------

MIX_RADII = (1.0, 1.5, 2.0)      # radii in ratio 5 : 3 : 2, as the broad phases' random gas
MIX_SHARES = (0.5, 0.3, 0.2)
MIX_RADII_PER_FRAME = 0.1        # mean speed: a tenth of the mean radius a frame at FPS


def shuffled_gas(n: int, packing: float, seed: int = 0, shuffle: bool = True) -> World:
    """n circles of the size mix in a square box at `packing`, without overlaps, moving in random
    directions, in a seeded random index order: what a gas's index order looks like once it has
    mixed (a lattice's index order is its cell order, which flatters any step that walks cells).
    shuffle=False: the same bodies in the order they were laid out, row by row."""
    rng = np.random.default_rng(seed)
    radii = rng.choice(MIX_RADII, size=n, p=MIX_SHARES)
    side = float(np.sqrt(np.pi * np.sum(radii ** 2) / packing))
    positions = shelves(radii, side, rng)
    velocities = random_velocities(n, MIX_RADII_PER_FRAME * float(np.mean(radii)) * FPS, rng)
    order = rng.permutation(n) if shuffle else np.arange(n)
    return World(positions[order], velocities[order], radii[order], box=(0.0, 0.0, side, side))


def shelves(radii: np.ndarray, side: float, rng) -> np.ndarray:
    """Centres for circles of these radii in a square of this side, without overlaps: rows as
    tall as the largest diameter, filled left to right in the given order, the room left in
    each row and above the last one spread between the circles, which then move at random
    within what room they have. (A square lattice cannot hold the size mix above packing 0.3.)"""
    pitch = 2.0 * float(radii.max()) * (1.0 + GAP)
    widths = 2.0 * radii * (1.0 + GAP)
    rows, row, used = [], [], 0.0
    for i, width in enumerate(widths):
        if used + width > side and row:
            rows.append(row)
            row, used = [], 0.0
        row.append(i)
        used += width
    rows.append(row)
    row_pitch = side / len(rows)
    if row_pitch < pitch or max(widths[row].sum() for row in rows) > side:
        raise ValueError(f"{len(radii)} circles of radius up to {radii.max():g} do not fit a box of side {side:.4g}")
    centres = np.empty((len(radii), 2))
    for k, row in enumerate(rows):
        spare = (side - widths[row].sum()) / len(row)          # room around each circle of the row
        left = np.concatenate([[0.0], np.cumsum(widths[row] + spare)[:-1]])
        x_room = 0.5 * spare
        y_room = 0.5 * (row_pitch - widths[row])
        centres[row, 0] = left + 0.5 * (widths[row] + spare) + rng.uniform(-1, 1, len(row)) * x_room
        centres[row, 1] = (k + 0.5) * row_pitch + rng.uniform(-1, 1, len(row)) * y_room
    return centres


# --- pyramids of boxes, for `collisim bench polygons` ----------------------------------------

PYRAMID_PITCH = 1.125     # unit boxes side by side with gaps of 1/8, each row set half a pitch in
PYRAMID_FRICTION = 0.6
PYRAMID_GRAVITY = 10.0


def pyramid_rows(base: int, x0: float) -> np.ndarray:
    """Centres of a pyramid of unit boxes standing on y = 0 from x0: `base` boxes in its bottom
    row, one fewer in each row above (base·(base + 1)/2 boxes)."""
    rows = [np.column_stack([x0 + 0.5 + (k / 2 + np.arange(base - k)) * PYRAMID_PITCH, np.full(base - k, 0.5 + k)])
            for k in range(base)]
    return np.concatenate(rows)


def pyramids(base: int, count: int = 1) -> World:
    """`count` pyramids of base `base` side by side on the floor of a box, e = 0, μ = 0.6, g = 10:
    pyramids(40) is 820 boxes, pyramids(10, 10) ten of 55."""
    from ...shapes import box

    width = (base - 1) * PYRAMID_PITCH + 1.0
    spacing = width + 2.0
    centres = np.concatenate([pyramid_rows(base, 1.0 + p * spacing) for p in range(count)])
    world_box = (0.0, 0.0, count * spacing + 1.0, base + 10.0)
    return World(centres, polygons=[box(1.0, 1.0)] * len(centres), angles=0.0, box=world_box,
                 gravity=(0.0, -PYRAMID_GRAVITY), restitution=0.0, friction=PYRAMID_FRICTION)


PYRAMIDS = {"pyramid40": lambda: pyramids(40), "pyramids10": lambda: pyramids(10, 10)}
