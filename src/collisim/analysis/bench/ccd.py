"""Benchmark: the event-driven `ccd` method's collisions per second, and its cost against plain pymunk.

For each gas of the accuracy benchmark (slow_gas, dense_gas, fast_gas: workloads.py) at each
size n (default 1 000 and 10 000; the box grows with n, so packing and speeds stay as named):

* plain pymunk's first loss-free substep count k: the accuracy benchmark's search
  (accuracy.lossless_substeps: 1, 2, 3, ... until no particle leaves the box), untimed, over the
  same simulated time as the timed runs, since a longer run may need more substeps;
* then `repeats` rounds, each timing ccd's run of the scene (as `simulate` streams it: the event
  loop's start, every block of frames) and plain pymunk's space.step calls at k substeps, one
  after the other, so both see the same load from elsewhere on a shared machine.

Reported per gas and size (the median over rounds, and the range):
  ccd_cost, pymunk_cost   wall seconds per simulated second;
  ccd_over_pymunk         ccd / pymunk at k, the ratio of the same round (the issue's budget: at
                          most 0.5);
  collisions_per_second   collisions ccd solved (every contact with a wall, a particle or a
                          segment, impulse or not) over the wall seconds of ccd's run: the
                          figure to compare with other engines;
  events_per_second       every event the loop processed: the collisions plus its bookkeeping
                          (cell crossings, slides off a segment's end: no velocity changes, but
                          each is predicted again like a collision), over the same seconds; the
                          crossings are counted apart (bookkeeping), never as collisions.
The run's counts come from the stepper's tally (CCDStepper.events_processed); every round
counts the same (the method is deterministic).

Before the rounds, one run of each kind on a two-frame scene compiles or loads the kernels.
Writes ccd.csv to the output folder.
"""
from __future__ import annotations

import pathlib
import sys
import time

import numpy as np

from ...core.files import write_table
from ...engine.simulate import METHODS, stream
from ..reference.plain_pymunk import time_plain_pymunk
from .accuracy import lossless_substeps, warm_up
from .workloads import WORKLOADS

GASES = ("slow_gas", "dense_gas", "fast_gas")
SIZES = (1_000, 10_000)
COLUMNS = ("workload", "n", "seconds", "pymunk_substeps", "ccd_cost", "pymunk_cost", "ccd_over_pymunk",
           "ccd_over_pymunk_low", "ccd_over_pymunk_high", "collisions_per_second", "collisions_per_second_low",
           "collisions_per_second_high", "events_per_second", "events_per_second_low", "events_per_second_high",
           "collisions", "bookkeeping")


def timed_ccd(scene) -> tuple:
    """(wall seconds, events processed by kind) of one ccd run of the scene, streamed as
    `simulate` streams it (the frames are made and dropped, not kept)."""
    start = time.perf_counter()
    scene = scene.replace(method="ccd")
    stepper = METHODS["ccd"](scene)
    for _ in stream(scene, stepper=stepper):
        pass
    return time.perf_counter() - start, stepper.events_processed()


def measure(workload: str, n: int, seconds: float, repeats: int) -> dict:
    """One CSV row: ccd against plain pymunk at its first loss-free substep count on this gas."""
    scene = WORKLOADS[workload](n=n).replace(seconds=seconds)
    substeps = lossless_substeps(scene)[0]
    if substeps is None:
        raise ValueError(f"{workload} n={n}: plain pymunk loses a particle at every substep count tried")
    warm_up(scene, "ccd", 1)
    ccd, pymunk, counts = [], [], None
    for _ in range(repeats):
        spent, counts = timed_ccd(scene)
        ccd.append(spent)
        pymunk.append(time_plain_pymunk(scene, substeps))
    ccd, pymunk = np.array(ccd), np.array(pymunk)
    ratios, events = ccd / pymunk, counts["collisions"] + counts["bookkeeping"]
    rates, collision_rates = events / ccd, counts["collisions"] / ccd
    return dict(workload=workload, n=n, seconds=seconds, pymunk_substeps=substeps,
                ccd_cost=float(np.median(ccd)) / seconds, pymunk_cost=float(np.median(pymunk)) / seconds,
                ccd_over_pymunk=float(np.median(ratios)), ccd_over_pymunk_low=float(ratios.min()),
                ccd_over_pymunk_high=float(ratios.max()), collisions_per_second=float(np.median(collision_rates)),
                collisions_per_second_low=float(collision_rates.min()),
                collisions_per_second_high=float(collision_rates.max()), events_per_second=float(np.median(rates)),
                events_per_second_low=float(rates.min()), events_per_second_high=float(rates.max()),
                collisions=counts["collisions"], bookkeeping=counts["bookkeeping"])


def run(out_dir, workloads=GASES, sizes=SIZES, seconds: float = 1.0, repeats: int = 3,
        progress: bool = True) -> dict:
    """Measure every gas at every size; write ccd.csv. Returns {"csv": path, "rows": [rows]}."""
    unknown = [name for name in workloads if name not in GASES]
    if unknown or repeats < 1 or not seconds > 0 or min(sizes) < 2:
        raise ValueError(f"unknown gas '{unknown[0]}'; choose from: {', '.join(GASES)}" if unknown
                         else "need repeats >= 1, seconds > 0 and sizes >= 2")
    rows = []
    for n in sizes:
        for workload in workloads:
            rows.append(measure(workload, n, seconds, repeats))
            if progress:
                print(format_row(rows[-1]), file=sys.stderr, flush=True)
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    path = out_dir / "ccd.csv"
    write_table(path, rows, COLUMNS)
    return {"csv": path, "rows": rows}


HEADER = (f"{'gas':<10} {'n':>6} {'pymunk':>7} {'ccd s/s':>8} {'pymunk s/s':>10} {'ccd / pymunk':>19} "
          f"{'collisions/s':>24} {'all events/s':>24} {'collisions':>10} {'crossings':>10}")


def format_row(row: dict) -> str:
    """One line: the costs, ccd / pymunk, collisions per second and all events (crossings
    included) per second, each as the median and its range."""
    return (f"{row['workload']:<10} {row['n']:>6} {'x' + str(row['pymunk_substeps']):>7} {row['ccd_cost']:8.4f} "
            f"{row['pymunk_cost']:10.4f} {row['ccd_over_pymunk']:6.2f} ({row['ccd_over_pymunk_low']:.2f}-"
            f"{row['ccd_over_pymunk_high']:.2f}) {_rate(row, 'collisions_per_second')} "
            f"{_rate(row, 'events_per_second')} {row['collisions']:10d} {row['bookkeeping']:10d}")


def _rate(row: dict, column: str) -> str:
    return f"{row[column]:9.3g} ({row[column + '_low']:.2g}-{row[column + '_high']:.2g})".rjust(24)


def format_table(rows: list) -> str:
    return "\n".join([HEADER] + [format_row(row) for row in rows])
