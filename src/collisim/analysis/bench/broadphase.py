"""Benchmark: time per frame of each broad-phase method as the particle count grows.

The particles are a random "gas": circles at uniform random positions in a
square sized so the circles cover ``packing`` of its area. Each method is
timed on the *second* of two frames (the particles nudged a little in
between), as the engine calls it, so sweep and prune profits from last
frame's order. A dashed reference line puts the numbers in context: scipy's
``cKDTree`` build + ``query_pairs(r=2 * max radius)``, a tuned C++ spatial index answering
a similar question (all centres closer than the largest possible contact distance).

The whole step is timed over many steps of a moving gas (workloads.shuffled_gas: the size mix,
no overlaps, in a seeded random index order, as a gas is once it has mixed; a lattice's index
order is its cell order and flatters every step that walks cells), at each packing, in the same
run as the references, each in its steady state: every engine first runs WARM_STEPS steps (5
simulated seconds), then runs of at least MIN_TIMED_STEPS steps are timed. The warm-up matters
for pymunk at large n: its bounding-box tree gives each shape a box fattened by its velocity over
0.1 s (Chipmunk's cpBBTree), and with every shape inserted at the same step they outgrow their
boxes together, so for the first few hundred steps every sixth or seventh step re-indexes most of
the gas. Two collisim lines:

* discrete_step: the engine alone (DiscreteStepper.run, grid), recording each frame into new
  arrays, as `simulate` has it do;
* simulate: `collisim.simulate(scene)` per frame, what a user calls (the world copied, the
  engine, the trajectory assembled), timed from the scene's start (no warm-up but compiling: it
  cannot carry on a state; the gas is mixed from its start).

The references:

* plain pymunk (collisim.analysis.reference.plain_pymunk): the Space a user would build, with
  Chipmunk's defaults and no collision callbacks, timing ``space.step(1/60)`` alone. (The
  comparison mirror, pymunk_mirror, with a Python callback on every contact and its own
  settings, is never used for speed.)
* the minimal compiled step (reference_step.py): one loop that moves and reflects at the walls,
  counting-sorts the rows into cell order, and applies elastic impulses to touching approaching
  pairs over the half 3×3 stencil — a yardstick for what a compiled step of this gas costs.

The CSV has a row per (packing, method, n); ``ns_per_particle`` is seconds_per_frame / n, and
collisim's rows carry ``step_over_pymunk`` and ``step_over_minimal``, its time divided by the
two references' at the same packing and n (the medians' ratio), and ``over_pymunk_range`` and
``over_minimal_range``, the lowest and highest ratio of one round's times.

Writes ``broadphase.csv`` and ``broadphase.png`` to the output folder.
"""

import pathlib
import sys
import time

import numpy as np

from collisim.broadphase import NAMES, make
from collisim.core.files import save_figure, write_table

BRUTE_MAX_N = 3000  # brute force above this would take minutes
RADII = (1.0, 1.5, 2.0)
RADIUS_SHARES = (0.5, 0.3, 0.2)  # 5 : 3 : 2
NUDGE = 0.05  # how far (in radii) particles move between the two frames
REFERENCES = ("scipy_ckdtree", "pymunk_step", "minimal_step", "discrete_step", "simulate")
COLLISIM = ("discrete_step", "simulate")     # the rows with ratios to the two step references
PACKINGS = (0.1, 0.3, 0.5)
COLUMNS = ("packing", "method", "n", "seconds_per_frame", "ns_per_particle", "candidates", "true_pairs",
           "step_over_pymunk", "step_over_minimal", "over_pymunk_range", "over_minimal_range")
STEP_WORK = 200_000   # particle-steps per timing of a whole step: 200 steps at n = 1000...
MIN_TIMED_STEPS = 21  # ...and at least this many (three of pymunk's re-indexing periods, see below)
WARM_STEPS = 300      # steps of every whole-step engine before it is timed: 5 simulated seconds
ABANDON_N = 100_000   # from this many bodies on, pymunk's space is never freed (PlainPymunk.abandon)


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


def moving_gas(n: int, packing: float, seed: int):
    """A Scene of workloads.shuffled_gas: n circles of the size mix at `packing`, no overlaps, in a
    random index order, moving about a tenth of a radius a frame at 60 fps."""
    import collisim

    from .workloads import shuffled_gas
    return collisim.Scene(world=shuffled_gas(n, packing, seed), fps=60, seconds=1.0, broadphase="grid")


def discrete_stepper(scene):
    """advance(steps) for collisim's discrete engine (grid) on the scene's world."""
    from collisim.engine.discrete import DiscreteStepper

    return DiscreteStepper(scene.world, scene.fps, 1, "grid").run


def pymunk_stepper(scene):
    """advance(steps) of plain pymunk space.step(1/60) on the same gas: the Space a user would
    build (reference/plain_pymunk.py: the World's masses and moments, elasticity = restitution,
    friction 0, walls as static segments, Chipmunk's defaults, no callbacks)."""
    from collisim.analysis.reference.plain_pymunk import PlainPymunk

    plain = PlainPymunk(scene.world)
    if scene.world.n >= ABANDON_N:
        plain.abandon()
    return lambda steps: plain.time_steps(scene.fps, steps)


def minimal_stepper(scene):
    """advance(steps) of the minimal compiled step (reference_step.py) on the same gas."""
    from .reference_step import MinimalStep

    return MinimalStep.from_world(scene.world, scene.fps).run


def simulate_stepper(scene):
    """advance(steps): collisim.simulate of the scene cut to `steps` frames (from its start)."""
    import collisim

    return lambda steps: collisim.simulate(scene.replace(seconds=steps / scene.fps))


STEPPERS = {"pymunk_step": pymunk_stepper, "minimal_step": minimal_stepper, "discrete_step": discrete_stepper,
            "simulate": simulate_stepper}
RESTARTING = ("simulate",)     # starts from the scene's start every call: warmed up (compiled) only


def time_whole_steps(scene, repeats: int, names=tuple(STEPPERS), warm_steps: int = WARM_STEPS) -> dict:
    """{name: median seconds per step} of each whole step (see whole_step_rounds)."""
    return {name: float(np.median(values)) for name, values in whole_step_rounds(scene, repeats, names,
                                                                                   warm_steps).items()}


def whole_step_rounds(scene, repeats: int, names=tuple(STEPPERS), warm_steps: int = WARM_STEPS) -> dict:
    """{name: seconds per step in each round} of each whole step on its own copy of the same gas, after
    `warm_steps` steps (compilation, and the steady state: see the module docstring), over runs of
    STEP_WORK / n steps (at least MIN_TIMED_STEPS). The repeats are rounds over the steppers, so
    a burst of load from elsewhere lands on one run of each rather than on every run of one."""
    advances = {name: STEPPERS[name](scene) for name in names}
    chunk = max(1, STEP_WORK // scene.world.n)   # collisim records each frame: warm up in runs this long
    for name, advance in advances.items():
        if name in RESTARTING:
            advance(2)
            continue
        for done in range(0, warm_steps, chunk):
            advance(min(chunk, warm_steps - done))
    steps = max(MIN_TIMED_STEPS, STEP_WORK // scene.world.n)
    seconds = {name: [] for name in names}
    for _ in range(repeats):
        for name, advance in advances.items():
            start = time.perf_counter()
            advance(steps)
            seconds[name].append((time.perf_counter() - start) / steps)
    return {name: np.array(values) for name, values in seconds.items()}


def time_discrete_step(scene, repeats: int) -> float:
    """Median seconds per step of collisim's discrete engine (grid) over a run of steps."""
    return time_whole_steps(scene, repeats, ("discrete_step",))["discrete_step"]


def time_pymunk(scene, repeats: int) -> float:
    """Median seconds per plain pymunk space.step(1/60) on the same gas (pymunk_stepper)."""
    return time_whole_steps(scene, repeats, ("pymunk_step",))["pymunk_step"]


def time_minimal_step(scene, repeats: int) -> float:
    """Median seconds per step of the minimal compiled step on the same gas."""
    return time_whole_steps(scene, repeats, ("minimal_step",))["minimal_step"]


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
    with tqdm(total=tasks, file=sys.stderr, disable=not progress, desc=f"packing {packing:g}") as bar:
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
                rows.append(dict(packing=packing, method=method, n=n, seconds_per_frame=seconds,
                                 candidates=len(pairs), true_pairs=true_pairs))
                bar.update()
            bar.set_postfix_str(f"n={n} cKDTree")
            seconds, found = time_ckdtree(moved, radii, repeats)
            rows.append(dict(packing=packing, method="scipy_ckdtree", n=n, seconds_per_frame=seconds,
                             candidates=found, true_pairs=true_pairs))
            bar.update()
            bar.set_postfix_str(f"n={n} whole steps")
            rounds = whole_step_rounds(moving_gas(n, packing, seed), repeats)
            for name, seconds in rounds.items():
                row = dict(packing=packing, method=name, n=n, seconds_per_frame=float(np.median(seconds)),
                           candidates="", true_pairs="")
                if name in COLLISIM:     # collisim / a reference in the same round: the range over rounds
                    for reference, column in (("pymunk_step", "over_pymunk_range"),
                                              ("minimal_step", "over_minimal_range")):
                        ratio = seconds / rounds[reference]
                        row[column] = f"{ratio.min():.2f}-{ratio.max():.2f}"
                rows.append(row)
                bar.update()
    return rows


def add_ratios(rows: list[dict]) -> list[dict]:
    """Fill ns_per_particle on every row, and collisim's ratios to the two step references
    (blank on the other rows)."""
    time_of = {(row["packing"], row["method"], row["n"]): row["seconds_per_frame"] for row in rows}
    for row in rows:
        row["ns_per_particle"] = 1e9 * row["seconds_per_frame"] / row["n"]
        row["step_over_pymunk"] = row["step_over_minimal"] = ""
        if row["method"] in COLLISIM:
            at = (row["packing"], row["n"])
            row["step_over_pymunk"] = row["seconds_per_frame"] / time_of[(at[0], "pymunk_step", at[1])]
            row["step_over_minimal"] = row["seconds_per_frame"] / time_of[(at[0], "minimal_step", at[1])]
    return rows


def write_csv(rows: list[dict], path: pathlib.Path) -> None:
    write_table(path, [{column: row.get(column, "") for column in COLUMNS} for row in rows], COLUMNS)


def plot(rows: list[dict], path: pathlib.Path) -> None:
    """Log-log time per frame vs n, a panel per packing: solid lines for the broad phases,
    dashed for the references and the whole steps."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    packings = sorted({row["packing"] for row in rows})
    figure = Figure(figsize=(6 * len(packings), 6), dpi=110)
    FigureCanvasAgg(figure)
    labels = {"scipy_ckdtree": "scipy cKDTree build + query_pairs",
              "pymunk_step": "plain pymunk Space.step (defaults, no callbacks)",
              "minimal_step": "minimal compiled step (reference_step.py)",
              "discrete_step": "collisim discrete step (engine alone, grid)",
              "simulate": "collisim.simulate() per frame"}
    for k, packing in enumerate(packings):
        axes = figure.add_subplot(1, len(packings), k + 1)
        for method in (*NAMES, *REFERENCES):
            mine = [row for row in rows if row["method"] == method and row["packing"] == packing]
            axes.plot([row["n"] for row in mine], [row["seconds_per_frame"] for row in mine],
                      linestyle="--" if method in REFERENCES else "-", marker="o", markersize=3,
                      label=labels.get(method, method))
        axes.set_xscale("log")
        axes.set_yscale("log")
        axes.set_xlabel("particles n")
        axes.set_ylabel("seconds per frame")
        axes.set_title(f"packing {packing:g}: broad phases on a random gas, whole steps on a shuffled gas",
                       fontsize=9)
        axes.grid(True, which="both", alpha=0.3)
        if k == 0:
            axes.legend(fontsize=7)
    figure.tight_layout()
    save_figure(figure, path)


def fastest_vs_ckdtree(rows: list[dict]) -> dict:
    """For each (packing, n): the fastest broad phase and its time divided by cKDTree's."""
    result = {}
    for at in sorted({(row["packing"], row["n"]) for row in rows}):
        here = [row for row in rows if (row["packing"], row["n"]) == at]
        reference = next(row["seconds_per_frame"] for row in here if row["method"] == "scipy_ckdtree")
        best = min((row for row in here if row["method"] in NAMES), key=lambda row: row["seconds_per_frame"])
        result[at] = {"method": best["method"], "ratio": best["seconds_per_frame"] / reference}
    return result


def ratios(rows: list[dict], method: str, column: str) -> dict:
    """{(packing, n): the column} of collisim's `method` rows (discrete_step or simulate)."""
    return {(row["packing"], row["n"]): row[column] for row in rows if row["method"] == method}


def run(out_dir: pathlib.Path, sizes=(100, 300, 1000, 3000, 10000, 30000, 100000), packings=PACKINGS,
        repeats=3, seed=0, progress=True) -> dict:
    """Time every method at every packing and size; write broadphase.csv and broadphase.png.

    Returns {"csv": path, "png": path, "rows": [CSV rows as dicts],
    "fastest_vs_ckdtree": {(packing, n): {"method": name, "ratio": fastest / cKDTree time}},
    "ratios": {(packing, n): {"engine / pymunk", "engine / minimal", "simulate / pymunk",
    "simulate / minimal"}}}.
    """
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    warm_up()
    rows = []
    for packing in packings:
        rows += measure(sizes, packing, repeats, seed, progress)
    rows = add_ratios(rows)
    csv_path, png_path = out_dir / "broadphase.csv", out_dir / "broadphase.png"
    write_csv(rows, csv_path)
    plot(rows, png_path)
    found = {}
    for method, label in (("discrete_step", "engine"), ("simulate", "simulate")):
        for reference, column in (("pymunk", "step_over_pymunk"), ("minimal", "step_over_minimal")):
            for at, ratio in ratios(rows, method, column).items():
                found.setdefault(at, {})[f"{label} / {reference}"] = ratio
    return {"csv": csv_path, "png": png_path, "rows": rows, "fastest_vs_ckdtree": fastest_vs_ckdtree(rows),
            "ratios": found}
