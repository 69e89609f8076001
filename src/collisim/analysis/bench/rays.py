"""`collisim bench rays`: ray queries through the 250-particle gas, per broad phase, against pymunk.

The world is the gas of scenes/particles_250.py at its start. `count` random rays (origins
uniform in the box, directions uniform, max_distance 10) are cast with collisim.raycast_many, once
per broad phase (one compiled call for all the rays, the structure built once per call), and
the same rays one by one through pymunk's Space.segment_query_first on a Space holding the same
circles and the four walls (static shapes), all in the same run. pymunk's figure includes a
Python call per ray: that is how a pymunk user casts many rays.

Each row: ns per ray (median of `repeats` timings of all the rays), the mean nodes, cells or
boxes the broad phase visited and bodies it tested per ray, and `agrees`: the share of rays
whose hit equals brute force's (collisim rows) or, for pymunk, the share of the rays starting
outside every circle on which distance, point and normal agree to 1e-9.
"""
from __future__ import annotations

import time

import numpy as np

import collisim
from collisim.broadphase import NAMES
from collisim.gas import lattice_gas

BOX = (0.0, 0.0, 32.0, 18.0)
REACH = 10.0
AGREEMENT = 1e-9


def gas_world() -> collisim.World:
    """The 250-particle gas of scenes/particles_250.py, at its start."""
    positions, velocities, radii = lattice_gas(250, box=BOX, speed=3.0, seed=7)
    return collisim.World(positions, velocities, radii, box=BOX)


def random_rays(count: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """origins (count, 2) uniform in the box and unit directions (count, 2) uniform in angle."""
    rng = np.random.default_rng(seed)
    origins = rng.uniform(BOX[:2], BOX[2:], (count, 2))
    angles = rng.uniform(0.0, 2.0 * np.pi, count)
    return origins, np.column_stack([np.cos(angles), np.sin(angles)])


def pymunk_space(world: collisim.World):
    """A pymunk Space with the world's circles and its four walls as static shapes."""
    import pymunk
    space = pymunk.Space()
    for (x, y), r in zip(world.positions, world.radii):
        space.add(pymunk.Circle(space.static_body, float(r), offset=(float(x), float(y))))
    x0, y0, x1, y1 = (float(v) for v in world.box)
    for a, b in (((x0, y0), (x0, y1)), ((x1, y0), (x1, y1)), ((x0, y0), (x1, y0)), ((x0, y1), (x1, y1))):
        space.add(pymunk.Segment(space.static_body, a, b, 0.0))
    return space


def time_collisim(world, origins, directions, name: str, repeats: int):
    """Median seconds of raycast_many over all the rays (compiled beforehand), and its hits."""
    collisim.raycast_many(world, origins[:2], directions[:2], REACH, broadphase=name)  # compile
    seconds = []
    for _ in range(repeats):
        start = time.perf_counter()
        hits = collisim.raycast_many(world, origins, directions, REACH, broadphase=name)
        seconds.append(time.perf_counter() - start)
    return float(np.median(seconds)), hits


def time_pymunk(space, origins, directions, repeats: int):
    """Median seconds of segment_query_first over all the rays, one call each, and the
    answers (pymunk.SegmentQueryInfo or None per ray)."""
    import pymunk
    everything = pymunk.ShapeFilter()
    starts = [tuple(point) for point in origins.tolist()]
    ends = [tuple(point) for point in (origins + REACH * directions).tolist()]
    seconds = []
    for _ in range(repeats):
        start = time.perf_counter()
        answers = [space.segment_query_first(a, b, 0.0, everything) for a, b in zip(starts, ends)]
        seconds.append(time.perf_counter() - start)
    return float(np.median(seconds)), answers


def same_hits(a, b) -> np.ndarray:
    """(m,) bool: rays on which two RayHits agree exactly."""
    return ((a.kinds == b.kinds) & (a.indices == b.indices) & (a.inside == b.inside)
            & ((a.distance == b.distance) | (np.isinf(a.distance) & np.isinf(b.distance))))


def pymunk_agreement(hits, answers, origins, world) -> float:
    """The share of the rays starting outside every circle on which pymunk's first hit has the
    same distance, point and normal as collisim's, to 1e-9."""
    distance = np.hypot(*(origins[:, None, :] - world.positions[None]).transpose(2, 0, 1))
    outside = np.flatnonzero((distance > world.radii).all(axis=1))
    agree = 0
    for k in outside:
        info = answers[k]
        if info is None:
            agree += int(hits.kinds[k] < 0)
            continue
        agree += int(abs(info.alpha * REACH - hits.distance[k]) <= AGREEMENT
                     and np.abs(np.subtract(tuple(info.point), hits.points[k])).max() <= AGREEMENT
                     and np.abs(np.subtract(tuple(info.normal), hits.normals[k])).max() <= AGREEMENT)
    return agree / max(len(outside), 1)


def bench_rays(count: int = 100_000, repeats: int = 3, seed: int = 0, broadphases=NAMES) -> list[dict]:
    """Rows {method, ns_per_ray, visited, tested, agrees}: one per collisim broad phase, then
    pymunk (visited and tested nan: pymunk does not say)."""
    world = gas_world()
    origins, directions = random_rays(count, seed)
    reference = collisim.raycast_many(world, origins, directions, REACH, broadphase="brute")
    rows = []
    for name in broadphases:
        seconds, hits = time_collisim(world, origins, directions, name, repeats)
        rows.append({"method": name, "ns_per_ray": 1e9 * seconds / count, "visited": float(hits.visited.mean()),
                     "tested": float(hits.tested.mean()), "agrees": float(same_hits(hits, reference).mean())})
    seconds, answers = time_pymunk(pymunk_space(world), origins, directions, repeats)
    rows.append({"method": "pymunk", "ns_per_ray": 1e9 * seconds / count, "visited": float("nan"),
                 "tested": float("nan"), "agrees": pymunk_agreement(reference, answers, origins, world)})
    return rows


def format_rays(rows: list[dict]) -> str:
    """The rows as a text table."""
    lines = [f"{'method':<12} {'ns/ray':>9} {'visited':>8} {'tested':>8} {'agrees':>8}"]
    for row in rows:
        visited = "-" if np.isnan(row["visited"]) else f"{row['visited']:.1f}"
        tested = "-" if np.isnan(row["tested"]) else f"{row['tested']:.1f}"
        lines.append(f"{row['method']:<12} {row['ns_per_ray']:>9.0f} {visited:>8} {tested:>8} "
                     f"{100 * row['agrees']:>7.2f}%")
    return "\n".join(lines)
