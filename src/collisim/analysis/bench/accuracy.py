"""Benchmark: what each method's accuracy costs, measured against the exact event-driven method.

Every workload of collisim.analysis.bench.workloads runs under
  * collisim's discrete steps at 1, 2, 4, 8, 16, 32 and 64 substeps per frame (grid broad phase,
    so the engine takes its fused compiled path: the fastest discrete configuration);
  * collisim's ccd: exact event-driven motion, the reference for every error below;
  * pymunk (Chipmunk2D) at 1, 2, 4, 8, 16 and 32 substeps per frame, the widely used impulse
    engine a user would otherwise reach for, as a user would run it: plain pymunk
    (collisim.analysis.reference.plain_pymunk), Chipmunk's default settings, no callbacks, thin
    static segments as walls;
  * and two more rows that are not part of the grid above: pymunk at the first substep count
    that loses no particle, when that count is not one of the six (found by trying 1, 2, 3, ...
    with plain pymunk, see `lossless_substeps`), and "pymunk mirror x1 (callbacks)": the
    comparison mirror (reference/pymunk_mirror.py: a Python callback on every contact, tiny
    slop, 30 iterations), which `collisim compare` uses to check physics. It is shown so that
    its cost is seen beside plain pymunk's, never as the speed baseline, and it is left out of
    the Pareto fronts.

Cost: wall seconds per simulated second, the median of `repeats` runs of the simulation alone
(after a two-frame warm-up, so numba compilation or cache loading is not counted; no metric
runs inside the timing). The runs go in rounds over all configurations of a workload, so a
burst of load from elsewhere on a shared machine is not charged to one configuration. A plain
pymunk run is timed as a user would step it: space.step calls and nothing else, no state read
(building the Space, a few milliseconds of Python, is not counted). Its errors come from a
separate, untimed run of the same Space that reads every frame and every touching arbiter
through pymunk's batch API. The mirror's cost is the time of its space.step calls, callbacks
included.

Errors, one CSV column each (collisim.analysis.metrics defines them):
  energy_drift     |E_end − E_0| / E_0 (kinetic plus potential): an elastic world keeps it;
  max_overlap      deepest pair overlap seen in any frame, in radii: ccd never overlaps;
  lost             particles whose centre was beyond a wall in some frame (metrics.outside,
                   "ever"). Plain pymunk's walls are thin segments, as a user writes them: such
                   a particle has escaped for good. The mirror's thick walls push it back in
                   later, so on its row this counts a visible failure, not an escape;
  missed           pairs that passed through each other within a frame, never pushed apart;
  position_error   RMS distance from ccd's particles at 0.25 s, in radii. In the slow and
                   dense gases and the bounces this is early enough to show each method's
                   own error; in the fast gas a particle has had about three collisions by
                   then, each multiplying a difference about twenty-fold (the mean free path
                   is ~11 radii), so every configuration ends up 10-25 radii off (discrete
                   x256 and x1024, 2e-3 radii apart after one frame, are 7 apart at 0.25 s):
                   there it ranks little;
  pressure_error   |P − P_ccd| / P_ccd for the mean wall pressure over the run (its scatter
                   from the finite number of wall hits is a few per cent in the slow gas).
ccd's own rows measure round-off: its position and pressure errors are 0 by definition.

Each workload gets a figure with one panel per error against cost on log axes, and the Pareto
front of that panel (the configurations no other is both faster and more accurate than) as a
step line: the cheapest way to reach each accuracy. The budget figures say what the exact
method costs in units of the engine one would otherwise use: ccd's time over pymunk x1's on
the two slow gases, and on the fast gas over pymunk at the first substep count that loses no
particle (pymunk at fewer substeps is not an alternative there); and, for the record, what the
mirror's callbacks cost: the mirror x1 over plain pymunk x1.

Writes accuracy.csv and accuracy_<workload>.png to the output folder.
"""
from __future__ import annotations

import pathlib
import sys
import time
import warnings
from dataclasses import dataclass

import numpy as np

from ...core.files import save_figure, write_table
from .. import metrics
from ..compare import measure, method_label, run_method
from ..reference.plain_pymunk import simulate_plain_pymunk, time_plain_pymunk
from ..reference.pymunk_mirror import simulate_pymunk
from .workloads import WORKLOADS

DISCRETE_SUBSTEPS = (1, 2, 4, 8, 16, 32, 64)
PYMUNK_SUBSTEPS = (1, 2, 4, 8, 16, 32)
BROADPHASE = "grid"   # with no segments, the grid runs the discrete step fused (engine/fused.py)
HORIZON = 0.25        # seconds: when positions are compared with ccd's
WARM_UP_FRAMES = 2
LOSSLESS_SEARCH_MAX = 64   # the most pymunk substeps tried when looking for one that loses no particle
MIRROR = ("pymunk_mirror", 1)
MIRROR_LABEL = "pymunk mirror x1 (callbacks)"


@dataclass(frozen=True)
class ErrorKind:
    """One error column, and how its panel shows it. Zeros cannot sit on a log axis: they are
    drawn at `floor`, and the axis label says so."""
    column: str
    label: str
    floor: float


ERRORS = (
    ErrorKind("energy_drift", "relative energy drift", 1e-17),
    ErrorKind("max_overlap", "largest overlap [radii]", 1e-17),
    ErrorKind("lost", "particles lost from the box (ever)", 0.1),
    ErrorKind("missed", "missed collisions (total)", 0.1),
    ErrorKind("position_error", f"position error at {HORIZON:g} s vs ccd [RMS radii]", 1e-17),
    ErrorKind("pressure_error", "wall-pressure error vs ccd [relative]", 1e-17),
)
COLUMNS = ("workload", "method", "engine", "substeps", "seconds", "cost", *(e.column for e in ERRORS),
           "pair_collisions", "wall_pressure", "notes")
STYLE = {"discrete": ("C0", "o"), "ccd": ("C3", "*"), "pymunk": ("C2", "s"), "pymunk_mirror": ("C2", "D")}
LEGEND = {"pymunk": "pymunk (plain, defaults)", "pymunk_mirror": "pymunk mirror (callbacks), not a baseline"}


def configurations() -> list:
    """(engine, substeps) of every configuration of the grid, in the CSV's order (ccd, the
    reference, first). Each workload adds the extra rows of `extra_configurations`."""
    return ([("ccd", 1)] + [("discrete", k) for k in DISCRETE_SUBSTEPS]
            + [("pymunk", k) for k in PYMUNK_SUBSTEPS])


def extra_configurations(lossless) -> list:
    """The rows added to the grid: pymunk at the lossless substep count (when the grid lacks it)
    and the mirror."""
    extra = [("pymunk", lossless)] if lossless is not None and ("pymunk", lossless) not in configurations() else []
    return extra + [MIRROR]


def label(engine: str, substeps: int) -> str:
    return MIRROR_LABEL if (engine, substeps) == MIRROR else method_label(engine, substeps)


def timed_run(scene, engine: str, substeps: int) -> tuple:
    """(trajectory or None, wall seconds) of one run of the scene: the simulation alone.

    Plain pymunk is only stepped (no trajectory: see the module docstring); the mirror's time is
    that of its space.step calls with their callbacks."""
    if engine == "pymunk":
        return None, time_plain_pymunk(scene, substeps)
    if engine == "pymunk_mirror":
        traj = simulate_pymunk(scene, substeps=substeps)
        return traj, traj.profile["step"]
    with warnings.catch_warnings():   # ccd's event-budget warning is kept in the trajectory
        warnings.simplefilter("ignore")
        start = time.perf_counter()
        traj = run_method(scene, engine, substeps)
        return traj, time.perf_counter() - start


def lossless_substeps(scene, limit: int = LOSSLESS_SEARCH_MAX) -> tuple:
    """(k, {substeps: recorded plain pymunk trajectory}): k is the first substep count 1, 2, 3, ...
    at which plain pymunk loses no particle (metrics.outside, ever), None if none up to `limit`;
    the dict holds every run tried, for reuse."""
    tried = {}
    for k in range(1, limit + 1):
        tried[k] = simulate_plain_pymunk(scene, k)
        if metrics.outside(tried[k], scene.world)[1] == 0:
            return k, tried
    return None, tried


def warm_up(scene, engine: str, substeps: int) -> None:
    """Compile (or load from numba's cache) the method's kernels outside any timing."""
    timed_run(scene.replace(seconds=WARM_UP_FRAMES / scene.fps), engine, substeps)


def relative_error(value: float, reference: float) -> float:
    if reference == 0:
        return 0.0 if value == 0 else float("inf")
    return abs(value - reference) / abs(reference)


def error_row(workload: str, scene, engine: str, substeps: int, traj, reference) -> dict:
    """One CSV row: the configuration and its errors against the ccd trajectory (cost: None,
    filled in once every round is timed)."""
    measured = measure(scene.world, traj, reference, HORIZON)
    reference_pressure = metrics.wall_pressure(reference, scene.world)
    return dict(
        workload=workload, method=label(engine, substeps), engine=engine, substeps=substeps,
        seconds=scene.frames / scene.fps, cost=None,
        energy_drift=measured["energy_drift"], max_overlap=measured["max_overlap"],
        lost=measured["outside_ever"], missed=measured["missed_pairs"],
        position_error=measured["position_error"],
        pressure_error=relative_error(measured["wall_pressure"], reference_pressure),
        pair_collisions=measured["pair_collisions"], wall_pressure=measured["wall_pressure"],
        notes="; ".join(measured["warnings"]))


def measure_workload(workload: str, scene, repeats: int, bar) -> list:
    """Every configuration's row for one scene; ccd runs first, as everyone's reference.

    First plain pymunk is recorded at 1, 2, 3, ... substeps until it loses no particle
    (lossless_substeps; untimed). The repeats are then rounds over all configurations, not
    back-to-back runs of each: on a shared machine a burst of load from elsewhere then lands on
    one run of several configurations (and the median drops it) rather than on every run of
    one. Errors come from the first round (every method is deterministic; plain pymunk's from
    its recorded runs), so only the ccd trajectory is kept."""
    bar.set_postfix_str(f"{workload} pymunk loss-free search")
    lossless, recorded = lossless_substeps(scene)
    configs = configurations() + extra_configurations(lossless)
    bar.total += (len(configs) - len(configurations())) * repeats   # the extra rows
    bar.refresh()
    for engine, substeps in configs:
        warm_up(scene, engine, substeps)
    seconds = {config: [] for config in configs}
    rows, reference = [], None
    for round_index in range(repeats):
        for engine, substeps in configs:
            bar.set_postfix_str(f"{workload} {label(engine, substeps)}")
            traj, spent = timed_run(scene, engine, substeps)
            seconds[(engine, substeps)].append(spent)
            if round_index == 0:
                reference = traj if engine == "ccd" else reference
                if engine == "pymunk":
                    traj = recorded[substeps] if substeps in recorded else simulate_plain_pymunk(scene, substeps)
                row = error_row(workload, scene, engine, substeps, traj, reference)
                if engine == "pymunk" and substeps == lossless and lossless > 1:
                    row["notes"] = "; ".join(filter(None, ["first pymunk substep count that loses no particle",
                                                           row["notes"]]))
                rows.append(row)
            bar.update()
    simulated = scene.frames / scene.fps
    for row, config in zip(rows, configs):
        row["cost"] = float(np.median(seconds[config])) / simulated
    return rows


# --- output ------------------------------------------------------------------------------------

def write_csv(rows: list, path: pathlib.Path) -> None:
    write_table(path, rows, COLUMNS)


def pareto_front(costs, errors) -> list:
    """Indices of the points no other point beats on both cost and error, by increasing cost
    (each has a smaller error than every cheaper one)."""
    front, best = [], float("inf")
    for index in sorted(range(len(costs)), key=lambda i: (costs[i], errors[i])):
        if errors[index] < best:
            front.append(index)
            best = errors[index]
    return front


def plot_workload(rows: list, path: pathlib.Path, title: str) -> None:
    """One panel per error kind: error against cost, log-log, with the Pareto front as steps."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    figure = Figure(figsize=(15, 9), dpi=110)
    FigureCanvasAgg(figure)
    panels = figure.subplots(2, 3, sharex=True).ravel()   # every panel has the same costs
    for axes, kind in zip(panels, ERRORS):
        plot_error(axes, rows, kind)
    for axes in panels[3:]:
        axes.set_xlabel("wall seconds per simulated second")
    panels[0].legend(loc="best", fontsize=8)
    figure.suptitle(f"Accuracy against cost: {title} (errors vs ccd, the exact method)")
    figure.tight_layout()
    save_figure(figure, path)


def plot_error(axes, rows: list, kind: ErrorKind) -> None:
    from matplotlib.ticker import FuncFormatter, LogLocator, NullFormatter

    costs = [row["cost"] for row in rows]
    errors = [max(float(row[kind.column]), kind.floor) for row in rows]   # zeros sit on the floor
    candidates = [i for i, row in enumerate(rows) if row["engine"] != "pymunk_mirror"]   # not a baseline
    front = [candidates[k] for k in pareto_front([costs[i] for i in candidates], [errors[i] for i in candidates])]
    axes.step([costs[i] for i in front], [errors[i] for i in front], where="post", color="0.5",
              linewidth=1, zorder=1, label="Pareto front")
    for engine, (colour, marker) in STYLE.items():
        mine = [i for i, row in enumerate(rows) if row["engine"] == engine]
        if not mine:
            continue
        hollow = engine == "pymunk_mirror"
        axes.scatter([costs[i] for i in mine], [errors[i] for i in mine], marker=marker,
                     facecolors="none" if hollow else colour, edgecolors=colour,
                     s=70 if engine == "ccd" else 30, zorder=2, label=LEGEND.get(engine, engine))
        for i in mine:
            if engine != "ccd":
                axes.annotate(f"x{rows[i]['substeps']}", (costs[i], errors[i]), xytext=(3, 3),
                              textcoords="offset points", fontsize=7, color=colour)
    axes.set_xscale("log")
    axes.set_yscale("log")
    # costs span a decade or two: label 1, 2, 5 of each decade, plainly (minor labels overlap)
    axes.xaxis.set_major_locator(LogLocator(subs=(1.0, 2.0, 5.0)))
    axes.xaxis.set_major_formatter(FuncFormatter(lambda value, _: f"{value:g}"))
    axes.xaxis.set_minor_formatter(NullFormatter())
    axes.set_ylabel(f"{kind.label}\n(0 plotted at {kind.floor:g})", fontsize=9)
    axes.grid(True, which="both", alpha=0.3)


# --- budget ------------------------------------------------------------------------------------

def budget(rows: list) -> dict:
    """What ccd costs in (plain) pymunk runs: ccd / pymunk x1 on the slow and dense gases; per
    workload the first pymunk substep count that loses no particle (the rows hold every count
    below it that the search tried and that lost one, or none when the search found none), and
    on the fast gas ccd / that run; and the mirror x1 / plain pymunk x1 per workload."""
    cost = {(row["workload"], row["method"]): row["cost"] for row in rows}
    figures = {"ccd_over_pymunk_x1": {}, "lossless_pymunk_substeps": {}, "fast_gas_lossless_pymunk_substeps": None,
               "fast_gas_ccd_over_lossless_pymunk": None, "mirror_over_pymunk_x1": {}}
    for workload in ("slow_gas", "dense_gas"):
        if (workload, "ccd") in cost:
            figures["ccd_over_pymunk_x1"][workload] = cost[(workload, "ccd")] / cost[(workload, "pymunk x1")]
    for workload in dict.fromkeys(row["workload"] for row in rows):
        if (workload, MIRROR_LABEL) in cost:
            figures["mirror_over_pymunk_x1"][workload] = cost[(workload, MIRROR_LABEL)] / cost[(workload, "pymunk x1")]
        lossless = [row for row in rows if row["workload"] == workload and row["engine"] == "pymunk"
                    and row["lost"] == 0]
        first = min(lossless, key=lambda row: row["substeps"]) if lossless else None
        figures["lossless_pymunk_substeps"][workload] = first and first["substeps"]
        if workload == "fast_gas" and first is not None:
            figures["fast_gas_lossless_pymunk_substeps"] = first["substeps"]
            figures["fast_gas_ccd_over_lossless_pymunk"] = cost[("fast_gas", "ccd")] / first["cost"]
    return figures


def run(out_dir, workloads=None, seconds: float = 10.0, repeats: int = 3, progress: bool = True) -> dict:
    """Run every configuration on every workload (default: all of WORKLOADS) for `seconds`;
    write accuracy.csv and accuracy_<workload>.png.

    Returns {"csv": path, "png": {workload: path}, "rows": [CSV rows as dicts],
    "budget": {"ccd_over_pymunk_x1": {workload: ratio}, "lossless_pymunk_substeps": {workload:
    substeps or None}, "fast_gas_lossless_pymunk_substeps": substeps or None,
    "fast_gas_ccd_over_lossless_pymunk": ratio or None, "mirror_over_pymunk_x1": {workload: ratio}}}.
    Every pymunk ratio is against plain pymunk (reference/plain_pymunk.py).
    """
    from tqdm import tqdm

    names = list(WORKLOADS) if workloads is None else list(workloads)
    unknown = [name for name in names if name not in WORKLOADS]
    if unknown:
        raise ValueError(f"unknown workload '{unknown[0]}'; choose from: {', '.join(WORKLOADS)}")
    if int(repeats) != repeats or repeats < 1:
        raise ValueError(f"repeats must be a whole number >= 1, got {repeats}")
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    rows, pngs = [], {}
    with tqdm(total=len(names) * len(configurations()) * repeats, file=sys.stderr, disable=not progress,
              desc="accuracy") as bar:
        for name in names:
            scene = WORKLOADS[name]().replace(seconds=seconds, broadphase=BROADPHASE)
            mine = measure_workload(name, scene, repeats, bar)
            pngs[name] = out_dir / f"accuracy_{name}.png"
            plot_workload(mine, pngs[name], f"{name} ({scene.description}, {seconds:g} s)")
            rows.extend(mine)
    csv_path = out_dir / "accuracy.csv"
    write_csv(rows, csv_path)
    return {"csv": csv_path, "png": pngs, "rows": rows, "budget": budget(rows)}
