"""Benchmark: peak memory of simulate() against the size of the trajectory it returns.

A moving gas (bench broadphase's, auto broad phase) of n bodies for a number of frames at 60 fps,
simulated in a fresh process with each storage (simulate's storage=). The process reports its peak
resident memory (getrusage, as /usr/bin/time -v does), what was resident just before simulate()
(the interpreter, numpy, numba, cv2 and the world; the kernels are compiled or loaded on a small
gas first, so that the peak is the run's), and the bytes the trajectory holds (its per-frame
arrays, counting a row repeated by a stride-0 view once, and its events).

    python -m collisim.analysis.bench.memory --n 1000000 --frames 60

prints one line per storage: peak / trajectory, counting the process's resident memory before the
run and without it.
"""
from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys


STORAGES = ("float64", "float32", "positions")


def held_bytes(trajectory) -> dict:
    """Bytes the trajectory's frames and events hold (a view repeating one row counts once)."""
    frames = 0
    for name in ("times", "positions", "velocities", "angles", "angular_velocities", "wall_collisions",
                 "pair_collisions", "segment_collisions", "candidates", "approximate"):
        array = getattr(trajectory, name)
        frames += array[0].nbytes if len(array) and array.strides[0] == 0 else array.nbytes
    events = sum(getattr(trajectory.events, name).nbytes for name in ("time", "kind", "i", "j", "impulse", "point"))
    return {"frames": frames, "events": events}


def resident_bytes() -> int:
    """What the process holds in memory now (Linux: /proc/self/statm)."""
    with open("/proc/self/statm") as file:
        return int(file.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def measure(n: int, frames: int, storage: str) -> dict:
    """Run in this process (call it in a fresh one): the figures for one storage."""
    import collisim
    from .broadphase import moving_gas

    collisim.simulate(moving_gas(2000, 0.1, 0).replace(broadphase="auto", seconds=2 / 60))  # compile or load
    scene = moving_gas(n, 0.1, 0).replace(broadphase="auto", seconds=frames / 60)
    before = resident_bytes()
    trajectory = collisim.simulate(scene, storage=storage)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024
    held = held_bytes(trajectory)
    total = held["frames"] + held["events"]
    return {"n": n, "frames": trajectory.frames, "storage": storage, "broadphase": trajectory.broadphase,
            "peak_bytes": peak, "resident_before_bytes": before, "trajectory_bytes": total,
            "peak_over_trajectory": peak / total, "run_over_trajectory": (peak - before) / total}


def run(n: int = 1_000_000, frames: int = 60, storages=STORAGES) -> list[dict]:
    """One fresh process per storage (a peak is a process's high-water mark)."""
    rows = []
    for storage in storages:
        code = (f"import json; from collisim.analysis.bench.memory import measure; "
                f"print(json.dumps(measure({n}, {frames}, {storage!r})))")
        result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
        rows.append(json.loads(result.stdout.strip().splitlines()[-1]))
    return rows


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--n", type=int, default=1_000_000)
    parser.add_argument("--frames", type=int, default=60)
    parser.add_argument("--storage", choices=STORAGES, nargs="+", default=STORAGES)
    args = parser.parse_args(argv)
    gib = 2.0 ** 30
    for row in run(args.n, args.frames, args.storage):
        print(f"{row['storage']:>9}: n={row['n']} frames={row['frames']} ({row['broadphase']}): peak "
              f"{row['peak_bytes'] / gib:.2f} GiB, resident before the run {row['resident_before_bytes'] / gib:.2f} "
              f"GiB, trajectory {row['trajectory_bytes'] / gib:.2f} GiB; peak / trajectory "
              f"{row['peak_over_trajectory']:.2f}, (peak - before) / trajectory {row['run_over_trajectory']:.2f}")


if __name__ == "__main__":
    main()
