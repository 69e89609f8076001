"""The slides' hierarchy over whole scenes: each level's false-positive rate, and what counting costs.

    .venv/bin/python benchmarks/hierarchy.py [--repeats 3] [--scenes bounding_volumes polygons]

Rates: each scene simulated whole (discrete); over every frame, the pairs passing each level
(Trajectory.hierarchy) and the share of them whose shapes do not touch (false positives).

Cost: the engine counts once per recorded frame (narrowphase/hierarchy.py: the funnel over the
candidate pairs its broad phase found for the step, the exact level read from the step's own
manifolds). Measured in the same run, best of `repeats` each: simulate() of the scene, and for a
world with polygons its own profile's record phase (the counting and the copy of the frame into
the trajectory), so simulate() without counting takes the difference. A world of circles is not
counted; for it, count_levels alone over every recorded frame (one compiled loop on the pairs
of a broad-phase query on the bounding circles, exact tests included) says what counting would
cost. particles_250 runs 10 s, as the solver's benchmarks do.
"""
import argparse
import time

import numpy as np
from numba import njit

import collisim
from collisim.engine.discrete import DiscreteStepper
from collisim.model.trajectory import LEVELS
from collisim.engine.hierarchy import circle_pairs, count_levels, false_positive_rates

SECONDS = {"particles_250": 10.0}


@njit(cache=True)
def count_frames(bodies, broad, positions, angles, vertices, counts):
    """counts (F, 4) of every frame (positions (F, n, 2), angles (F, n)), the engine's way."""
    for f in range(positions.shape[0]):
        bodies.positions[:] = positions[f]
        bodies.angles[:] = angles[f]
        count_levels(bodies, circle_pairs(bodies, broad), vertices, counts[f])
    return counts


def best(repeats: int, run) -> float:
    times = []
    for _ in range(repeats):
        start = time.perf_counter()
        run()
        times.append(time.perf_counter() - start)
    return min(times)


def measure(name: str, repeats: int) -> dict:
    scene = collisim.load_scene(name)
    if name in SECONDS:
        scene = scene.replace(seconds=SECONDS[name])
    trajectory = collisim.simulate(scene)   # also the warm-up: every kernel compiled
    stepper = DiscreteStepper(scene.world, scene.fps, scene.substeps, scene.broadphase)
    bodies, broad = stepper.bodies, stepper.broad
    positions = np.ascontiguousarray(trajectory.positions, np.float64)
    angles = np.ascontiguousarray(np.broadcast_to(trajectory.angles, positions.shape[:2]), np.float64)
    counts = np.empty((len(positions), len(LEVELS)), np.int64)
    vertices = np.empty_like(bodies.body_vertices)
    count_frames(bodies, broad, positions, angles, vertices, counts)
    simulating = best(repeats, lambda: collisim.simulate(scene))
    polygons = bool((scene.world.shapes != 0).any())
    if polygons:
        counting = min(collisim.simulate(scene).profile.get("record", 0.0) for _ in range(repeats))
    else:
        counting = best(repeats, lambda: count_frames(bodies, broad, positions, angles, vertices, counts))
    without = simulating - counting if polygons else simulating
    return {"scene": name, "seconds": scene.seconds, "frames": trajectory.frames, "pairs": counts.sum(axis=0),
            "rates": false_positive_rates(counts), "same": np.array_equal(trajectory.hierarchy, counts),
            "simulate": simulating, "count": counting, "ratio": (without + counting) / without,
            "counted_in_engine": polygons}


def report(m: dict) -> str:
    lines = [f"{m['scene']}: {m['seconds']:g} s, {m['frames']} frames"]
    if m["counted_in_engine"]:
        lines.append(f"  Trajectory.hierarchy equals the recount: {m['same']}")
    for level, passed, rate in zip(LEVELS, m["pairs"], m["rates"]):
        lines.append(f"  {level:16s} {int(passed):7d} pair-frames pass, false positives {rate:6.1%}")
    where = "the engine's record phase" if m["counted_in_engine"] else "count_levels alone: not counted by the engine"
    lines.append(f"  cost: simulate {m['simulate']:.3f} s, counting {m['count']:.4f} s ({where}); "
                 f"simulate with / without counting = {m['ratio']:.3f}")
    return "\n".join(lines)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--scenes", nargs="+", default=["bounding_volumes", "polygons", "particles_250"])
    args = parser.parse_args()
    for name in args.scenes:
        print(report(measure(name, args.repeats)), flush=True)


if __name__ == "__main__":
    main()
