"""The 20 000-disk fast gas (analysis/bench/workloads.fast_gas, n = 20 000) under ccd through the
engine: whether any frame goes over the event budget, the energy drift and the largest overlap.

    .venv/bin/python benchmarks/ccd_fast_gas.py [seconds]
"""
import sys
import time

import numpy as np

import collisim
from collisim.analysis.bench.workloads import fast_gas
from collisim.broadphase import find_pairs


def main(seconds=2.0):
    scene = fast_gas(n=20_000).replace(method="ccd", seconds=seconds)
    start = time.perf_counter()
    traj = collisim.simulate(scene)
    elapsed = time.perf_counter() - start
    ke = traj.kinetic_energy()
    worst = 0.0
    for p in traj.positions:
        r = traj.radii
        pairs = find_pairs("grid", p - r[:, None], p + r[:, None])
        d = np.hypot(*(p[pairs[:, 0]] - p[pairs[:, 1]]).T)
        worst = max(worst, np.max((r[pairs].sum(axis=1) - d) / r[pairs].min(axis=1), initial=0.0))
    counts = traj.collisions
    print(f"fast gas, 20 000 disks, {seconds:g} s under ccd in {elapsed:.1f} s: approximate frames "
          f"{int(traj.approximate.sum())}, energy drift {np.abs(ke / ke[0] - 1).max():.2e}, "
          f"largest overlap {worst:.2e} r, collisions per frame up to {int(counts.max())}")


if __name__ == "__main__":
    main(*(float(a) for a in sys.argv[1:]))
