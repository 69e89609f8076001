"""Benchmark: time per frame of each broad-phase method as the particle count grows.

The particles are a random "gas": circles at uniform random positions in a
square sized so the circles cover ``packing`` of its area. Each method is
timed on the *second* of two frames (the particles nudged a little in
between), as the engine calls it, so sweep and prune profits from last
frame's order. Two dashed reference lines put the numbers in context:

* scipy's ``cKDTree`` build + ``query_pairs(r=2 * max radius)`` — a tuned C++
  spatial index answering a similar question (all centres closer than the
  largest possible contact distance);
* one ``pymunk`` ``Space.step(1/60)`` on the same circles — a whole physics
  step (broad phase, narrow phase and solver) of a real engine.

The whole discrete step (collisim's engine with the grid, integrate to walls) is timed
against pymunk's ``Space.step`` over many steps of the same moving gas, started without
overlaps (a jittered lattice at the same packing), so both run in their steady state.

Writes ``broadphase.csv`` and ``broadphase.png`` to the output folder.
"""

import csv
import pathlib
import sys
import time

import numpy as np

from collisim.broadphase import NAMES, make

BRUTE_MAX_N = 3000  # brute force above this would take minutes
RADII = (1.0, 1.5, 2.0)
RADIUS_SHARES = (0.5, 0.3, 0.2)  # 5 : 3 : 2
NUDGE = 0.05  # how far (in radii) particles move between the two frames
REFERENCES = ("scipy_ckdtree", "pymunk_step", "discrete_step")
STEP_WORK = 200_000   # particle-steps per timing of a whole step: 200 steps at n = 1000


def random_gas(n: int, packing: float, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """n circles, radii 1, 1.5 and 2 in ratio 5:3:2, at uniform random positions
    in a square whose area is the circles' total area / packing.

    Returns positions (n, 2) and radii (n,).
    """
    rng = np.random.default_rng(seed)
    radii = rng.choice(RADII, size=n, p=RADIUS_SHARES)
    side = np.sqrt(np.pi * np.sum(radii ** 2) / packing)
    return rng.uniform(0.0, side, size=(n, 2)), radii


def boxes(positions: np.ndarray, radii: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The circles' bounding boxes lo, hi: (n, 2)."""
    return positions - radii[:, None], positions + radii[:, None]


def touching_pairs(positions: np.ndarray, radii: np.ndarray, candidates: np.ndarray) -> int:
    """How many candidate pairs are circles that really touch or overlap."""
    i, j = candidates[:, 0], candidates[:, 1]
    distance = np.hypot(*(positions[i] - positions[j]).T)
    return int(np.count_nonzero(distance <= radii[i] + radii[j]))


def time_method(method: str, frame_a, frame_b, repeats: int) -> tuple[float, np.ndarray]:
    """Median seconds of .pairs(frame_b) right after .pairs(frame_a), and the pairs."""
    phase = make(method)
    seconds = []
    for _ in range(repeats):
        phase.pairs(*frame_a)
        start = time.perf_counter()
        pairs = phase.pairs(*frame_b)
        seconds.append(time.perf_counter() - start)
    return float(np.median(seconds)), pairs


def time_ckdtree(positions: np.ndarray, radii: np.ndarray, repeats: int) -> tuple[float, int]:
    """Median seconds of cKDTree build + query_pairs(2 * max radius), and the pair count."""
    from scipy.spatial import cKDTree

    seconds = []
    for _ in range(repeats):
        start = time.perf_counter()
        pairs = cKDTree(positions).query_pairs(r=2 * radii.max(), output_type="ndarray")
        seconds.append(time.perf_counter() - start)
    return float(np.median(seconds)), len(pairs)


def moving_gas(n: int, packing: float, seed: int) -> "collisim.Scene":
    """n circles on a jittered lattice (no overlaps) in a box at `packing`, moving about a
    tenth of a radius per step: the steady state of a gas."""
    import collisim
    from collisim.gas import lattice_gas

    mean_area = np.pi * np.dot(np.square((0.22, 0.32, 0.45)), (0.5, 0.3, 0.2))
    side = np.sqrt(n * mean_area / packing)
    positions, velocities, radii = lattice_gas(n, box=(0.0, 0.0, side, side), speed=0.1 * 0.3 * 60, seed=seed)
    world = collisim.World(positions=positions, velocities=velocities, radii=radii, box=(0.0, 0.0, side, side))
    return collisim.Scene(world=world, fps=60, seconds=1.0, broadphase="grid")


def time_discrete_step(scene, repeats: int) -> float:
    """Median seconds per step of collisim's discrete engine (grid) over a run of steps."""
    from collisim.engine.discrete import DiscreteStepper

    stepper = DiscreteStepper(scene.world, scene.fps, 1, "grid")
    stepper.run(2)
    steps = max(5, STEP_WORK // scene.world.n)
    seconds = []
    for _ in range(repeats):
        start = time.perf_counter()
        stepper.run(steps)
        seconds.append((time.perf_counter() - start) / steps)
    return float(np.median(seconds))


def time_pymunk(scene, repeats: int) -> float:
    """Median seconds per pymunk Space.step(1/60) on the same gas, built by collisim's mirror
    (same masses and radii, elasticity 1, friction 0, walls) with Chipmunk's default 10 solver
    iterations, over a run of steps."""
    from collisim.analysis.reference.pymunk_mirror import Mirror

    space = Mirror(scene.world, iterations=10).space
    space.step(1 / 60)
    steps = max(5, STEP_WORK // scene.world.n)
    seconds = []
    for _ in range(repeats):
        start = time.perf_counter()
        for _ in range(steps):
            space.step(1 / 60)
        seconds.append((time.perf_counter() - start) / steps)
    return float(np.median(seconds))


def warm_up() -> None:
    """Compile (or load from numba's cache) every kernel before anything is
    timed: two frames each, so sweep and prune's order repair runs too."""
    positions, radii = random_gas(50, 0.1, 0)
    for method in NAMES:
        phase = make(method)
        phase.pairs(*boxes(positions, radii))
        phase.pairs(*boxes(positions + 0.01, radii))


def measure(sizes, packing: float, repeats: int, seed: int, progress: bool) -> list[dict]:
    """One row per (method or reference, n): the CSV's columns."""
    from tqdm import tqdm

    rows = []
    tasks = sum(len(NAMES) - (n > BRUTE_MAX_N) + len(REFERENCES) for n in sizes)
    with tqdm(total=tasks, file=sys.stderr, disable=not progress, desc="broad phase") as bar:
        for n in sizes:
            positions, radii = random_gas(n, packing, seed)
            moved = positions + np.random.default_rng(seed + 1).normal(0, NUDGE, positions.shape) * radii[:, None]
            frame_a, frame_b = boxes(positions, radii), boxes(moved, radii)
            true_pairs = touching_pairs(moved, radii, make("grid").pairs(*frame_b))
            for method in NAMES:
                if method == "brute" and n > BRUTE_MAX_N:
                    continue
                bar.set_postfix_str(f"n={n} {method}")
                seconds, pairs = time_method(method, frame_a, frame_b, repeats)
                rows.append(dict(method=method, n=n, seconds_per_frame=seconds,
                                 candidates=len(pairs), true_pairs=true_pairs))
                bar.update()
            bar.set_postfix_str(f"n={n} cKDTree")
            seconds, found = time_ckdtree(moved, radii, repeats)
            rows.append(dict(method="scipy_ckdtree", n=n, seconds_per_frame=seconds,
                             candidates=found, true_pairs=true_pairs))
            bar.update()
            gas = moving_gas(n, packing, seed)
            for name, timer in (("pymunk_step", time_pymunk), ("discrete_step", time_discrete_step)):
                bar.set_postfix_str(f"n={n} {name}")
                rows.append(dict(method=name, n=n, seconds_per_frame=timer(gas, repeats), candidates="",
                                 true_pairs=""))
                bar.update()
    return rows


def write_csv(rows: list[dict], path: pathlib.Path) -> None:
    with open(path, "w", newline="") as file:
        writer = csv.DictWriter(file, fieldnames=["method", "n", "seconds_per_frame", "candidates", "true_pairs"])
        writer.writeheader()
        writer.writerows(rows)


def plot(rows: list[dict], path: pathlib.Path, packing: float) -> None:
    """Log-log time per frame vs n: solid lines for the methods, dashed for the references."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(8, 5.5), dpi=120)
    FigureCanvasAgg(figure)
    axes = figure.add_subplot()
    labels = {"scipy_ckdtree": "scipy cKDTree build + query_pairs",
              "pymunk_step": "pymunk Space.step: a whole step of a moving gas",
              "discrete_step": "collisim discrete step (grid): a whole step of the same gas"}
    for method in (*NAMES, *REFERENCES):
        mine = [row for row in rows if row["method"] == method]
        axes.plot([row["n"] for row in mine], [row["seconds_per_frame"] for row in mine],
                  linestyle="--" if method in REFERENCES else "-", marker="o", markersize=3,
                  label=labels.get(method, method))
    axes.set_xscale("log")
    axes.set_yscale("log")
    axes.set_xlabel("particles n")
    axes.set_ylabel("seconds per frame")
    axes.set_title(f"Broad phases on a random gas, whole steps on a moving gas (packing {packing:g})")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend()
    figure.tight_layout()
    figure.savefig(path)


def fastest_vs_ckdtree(rows: list[dict]) -> dict:
    """For each n: the fastest method and its time divided by cKDTree's."""
    result = {}
    for n in sorted({row["n"] for row in rows}):
        at_n = [row for row in rows if row["n"] == n]
        reference = next(row["seconds_per_frame"] for row in at_n if row["method"] == "scipy_ckdtree")
        best = min((row for row in at_n if row["method"] in NAMES), key=lambda row: row["seconds_per_frame"])
        result[n] = {"method": best["method"], "ratio": best["seconds_per_frame"] / reference}
    return result


def discrete_vs_pymunk(rows: list[dict]) -> dict:
    """For each n: collisim's whole discrete step divided by pymunk's."""
    time_of = {(row["method"], row["n"]): row["seconds_per_frame"] for row in rows}
    return {n: time_of[("discrete_step", n)] / time_of[("pymunk_step", n)]
            for n in sorted({row["n"] for row in rows})}


def run(out_dir: pathlib.Path, sizes=(100, 300, 1000, 3000, 10000, 30000, 100000), packing=0.1,
        repeats=3, seed=0, progress=True) -> dict:
    """Time every method at every size; write broadphase.csv and broadphase.png.

    Returns {"csv": path, "png": path, "rows": [CSV rows as dicts],
    "fastest_vs_ckdtree": {n: {"method": name, "ratio": fastest / cKDTree time}},
    "discrete_vs_pymunk": {n: collisim step / pymunk step}}.
    """
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    warm_up()
    rows = measure(sizes, packing, repeats, seed, progress)
    csv_path, png_path = out_dir / "broadphase.csv", out_dir / "broadphase.png"
    write_csv(rows, csv_path)
    plot(rows, png_path, packing)
    return {"csv": csv_path, "png": png_path, "rows": rows, "fastest_vs_ckdtree": fastest_vs_ckdtree(rows),
            "discrete_vs_pymunk": discrete_vs_pymunk(rows)}

