"""Must-shows of ccd under gravity (issue 12, item 1):

* settle: the particles_250 gas with gravity (0, -9.81) and e = 0.8 under ccd, streamed block by
  block as a render does: seconds of compute per simulated second against discrete at 1 substep
  (same run, same scene; with its default sleeping and never asleep), the peak resident memory growth per 10 s block, the largest overlap
  (radii of the smaller body), events per simulated second, frames over budget;
* pile: 200 equal balls dropped at random into a box exactly 10 diameters wide, e = 0, 0.5,
  0.9: the largest overlap, the kinetic energy over the last second against the drop energy,
  the floor's support against the pile's weight, and the pile's height against hexagonal close
  packing of 200 balls in rows of 10 and 9, against the pymunk comparison mirror's pile from
  the same drop (10 substeps) and against the discrete method's; then, for each e, every
  engine's mean height over the seeds against close packing, and ccd's mean against the
  mirror's (one drop is chaotic: its height moves by several points with the seed).

    .venv/bin/python benchmarks/ccd_settling.py settle [seconds] [rest_speed]
    .venv/bin/python benchmarks/ccd_settling.py pile [seconds] [rest_speed] [seed ...]

rest_speed: ccd's Scene.rest_speed (engine/ccd/sleep.py); left out or "default", the Scene's
default. seed: the random drops of the pile (default 1).
"""
import resource
import sys
import time

import numpy as np

import collisim
from collisim.analysis.reference.pymunk_mirror import simulate_pymunk
from collisim.broadphase import find_pairs
from collisim.engine import stream
from collisim.core.kinds import SUPPORT, WALL

G = 9.81


def worst_overlap(positions, radii):
    pairs = find_pairs("grid", positions - radii[:, None], positions + radii[:, None])
    d = np.hypot(*(positions[pairs[:, 0]] - positions[pairs[:, 1]]).T)
    return float(np.max((radii[pairs].sum(axis=1) - d) / radii[pairs].min(axis=1), initial=0.0))


def peak_mb():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def settle(seconds=60.0, rest_speed=None):
    scene = collisim.load_scene("particles_250")
    scene = scene.replace(world=scene.world.copy(gravity=(0.0, -G), restitution=0.8), seconds=seconds,
                          rest_speed=rest_speed)
    costs = {}
    # the discrete method sleeps (engine/islands.py); never asleep, it costs what a gas does
    runs = {"discrete": scene.replace(method="discrete", substeps=1),
            "discrete never asleep": scene.replace(method="discrete", substeps=1, rest_speed=0.0),
            "ccd": scene.replace(method="ccd", substeps=1)}
    for method, run in runs.items():
        list(stream(run.replace(seconds=1 / 60 * 2)))  # compile
        start, worst, events, approximate, marks = time.perf_counter(), 0.0, 0, 0, []
        for block in stream(run, block=600):
            if method == "ccd":
                worst = max(worst, max(worst_overlap(p, block.radii) for p in block.positions))
                events += len(block.events)
                approximate += int(block.approximate.sum())
            marks.append((block.times[-1], time.perf_counter() - start, peak_mb()))
        costs[method] = (time.perf_counter() - start) / seconds
        if method == "ccd":
            print(f"ccd: {costs['ccd']:.3f} s per simulated second, {events / seconds:.0f} logged events per "
                  f"simulated second, {approximate} frames over budget, largest overlap {worst:.2e} r")
            print("  peak memory after each 10 s block (MB): " + ", ".join(f"{m:.0f}" for _, _, m in marks))
            print("  compute per 10 s block (s): " + ", ".join(
                f"{b - a:.2f}" for (_, a, _), (_, b, _) in zip([(0, 0.0, 0)] + marks[:-1], marks)))
    print(f"discrete x1: {costs['discrete']:.3f} s per simulated second; ccd / discrete = "
          f"{costs['ccd'] / costs['discrete']:.2f}")
    print(f"discrete x1 never asleep (rest_speed 0): {costs['discrete never asleep']:.3f} s per simulated second; "
          f"ccd / it = {costs['ccd'] / costs['discrete never asleep']:.2f}")


def pile_world(restitution, n=200, radius=0.5, columns=10, seed=1):
    width = 2 * radius * columns
    rng = np.random.default_rng(seed)
    pitch = width / (columns - 1)   # wider than a diameter: no two start touching
    x = (np.arange(n) % (columns - 1) + 0.5) * pitch + rng.uniform(-0.1, 0.1, n) * radius
    y = 3 * radius + (np.arange(n) // (columns - 1)) * 2.5 * radius
    height = y.max() + 2 * radius
    return collisim.World(np.column_stack([x, y]), rng.normal(0, 0.5, (n, 2)), radius, box=(0, 0, width, height),
                          gravity=(0.0, -G), restitution=restitution)


def close_packing_height(n=200, radius=0.5, columns=10):
    """Top of the pile of n balls in hexagonal rows of columns and columns - 1 (centre height of
    the top row + radius), a partial top row counted by its share."""
    left, rows = n, 0
    while left > 0:
        take = columns if rows % 2 == 0 else columns - 1
        if left < take:
            return radius + (rows - 1) * np.sqrt(3) * radius + (left / take) * np.sqrt(3) * radius + radius
        left, rows = left - take, rows + 1
    return radius + (rows - 1) * np.sqrt(3) * radius + radius


def top_of(traj):
    return float(np.max(traj.positions[-1, :, 1] + traj.radii))


def floor_share(traj, world):
    """The floor's support over the last second against the pile's weight (kinds.SUPPORT)."""
    last = (traj.events.time > traj.times[-1] - 1.0) & (traj.events.j == 2) & np.isin(traj.events.kind, (WALL, SUPPORT))
    return float(traj.events.impulse[last].sum() / (world.masses.sum() * G * 1.0))


def pile(seconds=20.0, rest_speed=None, seeds=(1,)):
    ref = close_packing_height()
    heights = {}   # (e, engine): the piles' heights, one per seed
    for seed in seeds:
        for e in (0.0, 0.5, 0.9):
            world = pile_world(e, seed=int(seed))
            scene = collisim.Scene(world=world, fps=60, seconds=seconds, method="ccd", rest_speed=rest_speed)
            start = time.perf_counter()
            traj = collisim.simulate(scene)
            elapsed = time.perf_counter() - start
            m = world.masses
            drop = float(np.sum(m * G * (world.positions[:, 1] - world.radii))
                         + 0.5 * np.sum(m[:, None] * world.velocities ** 2))
            ke = 0.5 * np.sum(m[None] * np.sum(traj.velocities ** 2, axis=2), axis=1)
            worst = max(worst_overlap(p, traj.radii) for p in traj.positions[::6])
            top = top_of(traj)
            discrete = top_of(collisim.simulate(scene.replace(method="discrete")))
            mirror = top_of(simulate_pymunk(scene, substeps=10))
            last = traj.times >= traj.times[-1] - 1.0
            for engine, height in (("ccd", top), ("pymunk mirror", mirror), ("discrete", discrete)):
                heights.setdefault((e, engine), []).append(height)
            print(f"seed {seed}, e = {e}: {elapsed:.1f} s for {seconds:g} s, largest overlap {worst:.2e} r, kinetic "
                  f"energy over the last second <= {ke[last].max() / drop:.1e} of the drop energy, frames over budget "
                  f"{int(traj.approximate.sum())}, floor support over the last second / weight "
                  f"{floor_share(traj, world):.12f}; height {top:.3f}: {(top / ref - 1) * 100:+.2f} % against hexagonal "
                  f"close packing ({ref:.3f}), {(top / mirror - 1) * 100:+.2f} % against the pymunk mirror's pile "
                  f"({mirror:.3f}, 10 substeps), {(top / discrete - 1) * 100:+.2f} % against the discrete pile "
                  f"({discrete:.3f})", flush=True)
    summarize_piles(heights, ref, len(seeds))


def summarize_piles(heights, ref, count):
    """Each engine's mean pile height over the seeds against close packing, and ccd's mean
    against the pymunk mirror's: a random drop jams above close packing in every engine, so the
    reference for ccd is the reference engine's piles from the same drops."""
    for e in sorted({e for e, _ in heights}):
        means = {engine: float(np.mean(h)) for (e2, engine), h in heights.items() if e2 == e}
        spread = ", ".join(f"{engine} {(m / ref - 1) * 100:+.2f} %" for engine, m in means.items())
        print(f"e = {e}, mean of {count} piles against close packing: {spread}; ccd against the pymunk mirror "
              f"{(means['ccd'] / means['pymunk mirror'] - 1) * 100:+.2f} %", flush=True)


if __name__ == "__main__":
    what = sys.argv[1] if len(sys.argv) > 1 else "settle"
    numbers = [None if a == "default" else float(a) for a in sys.argv[2:4]]
    if what == "pile" and len(sys.argv) > 4:   # pile seconds rest_speed seed [seed ...]
        numbers.append([int(a) for a in sys.argv[4:]])
    {"settle": settle, "pile": pile}[what](*numbers)
