"""ccd with one large disk among many small ones: the cell grid sized by the small ones (the
large disks kept apart, broadphase/cells.py) against cells sized by the largest diameter
(the old grid), in the same run. Prints seconds per simulated second and the ratio.

    .venv/bin/python benchmarks/ccd_mixed_sizes.py [n_small] [large_radius] [seconds] [repeats]
"""
import sys
import time

import numpy as np

from collisim.engine.ccd.events import simulate_events
from collisim.gas import lattice_gas


def mixed_gas(n_small: int, large_radius: float, seed: int = 3):
    """n_small small particles on a jittered lattice (the particles_250 density), those
    overlapping a large disk in the middle removed, the large disk added last."""
    side = np.sqrt(n_small / (250 / (32 * 18)))
    box = (0.0, 0.0, side * 4 / 3, side * 3 / 4)
    positions, velocities, radii = lattice_gas(n_small, box=box, speed=3.0, seed=seed)
    centre = np.array([box[2] / 2, box[3] / 2])
    keep = np.hypot(*(positions - centre).T) > large_radius + radii + 1e-3
    positions = np.vstack([positions[keep], centre])
    velocities = np.vstack([velocities[keep], [1.0, 0.5]])
    radii = np.append(radii[keep], large_radius)
    return positions, velocities, radii, np.array(box)


def run(positions, velocities, radii, box, seconds, separate_large):
    start = time.perf_counter()
    result = simulate_events(positions, velocities, (0.0, 0.0), radii, radii ** 2, box, 1.0, None, 1 / 60,
                             int(round(seconds * 60)), separate_large=separate_large)
    return time.perf_counter() - start, result


def main(n_small=48_000, large_radius=8.0, seconds=0.5, repeats=3):
    positions, velocities, radii, box = mixed_gas(n_small, large_radius)
    small = (positions[:1], velocities[:1], radii[:1], box)
    for flag in (True, False):   # compile both paths
        run(*small, 1 / 60, flag)
    print(f"{len(radii)} bodies (1 of radius {large_radius:g}, the others 0.22-0.45), {seconds:g} s simulated")
    ratios = []
    for _ in range(max(1, int(repeats))):
        old, a = run(positions, velocities, radii, box, seconds, False)
        new, b = run(positions, velocities, radii, box, seconds, True)
        same = np.array_equal(a.kind, b.kind) and np.array_equal(a.i, b.i) and np.array_equal(a.j, b.j)
        gap = float(np.abs(a.positions - b.positions).max())
        ratios.append(old / new)
        print(f"cells by largest: {old / seconds:7.2f} s/s   large kept apart: {new / seconds:7.2f} s/s   "
              f"ratio {old / new:5.1f}   same events: {same} ({len(a.time)}), largest position gap {gap:.1e}")
    print(f"ratio over {len(ratios)} repeats: {min(ratios):.1f} - {max(ratios):.1f}")


if __name__ == "__main__":
    args = [float(a) for a in sys.argv[1:]]
    main(*([int(args[0])] + args[1:3] + [int(a) for a in args[3:]]))
