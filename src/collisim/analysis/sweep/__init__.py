"""Sweeps: a grid of simulations from one TOML file, run serially or on Dask, one CSV row per job.

    collisim sweep FILE [--workers N | --scheduler ADDRESS] [--out PATH] [--fresh] [--plot]

The sweep file
--------------
    name = "tunnelling"        # optional (default: the file's name); names the table
    description = "..."        # optional
    measure = ["missed_segments", "collisions", "cost"]   # the table's measurements
    horizon = 0.25             # optional: when position_error compares with ccd [s]
    video = false              # optional: each job writes <table folder>/<table name>/<id>.mp4
    trajectory = false         # optional: ... and <id>.npz (collisim render <id>.npz plays it)

    [grid]                     # parameters to vary: the jobs are their Cartesian product
    workload = ["barrier"]     # or scene = ["particles_250", "scenes/mine.py"]
    method = ["discrete", "ccd"]
    speed = { geomspace = [0.5, 40.0, 25] }
    phase = { linspace = [0.025, 0.975, 20] }

    [[grid.cases]]             # optional, repeatable: the jobs are [grid] × (case 1 + case 2 + ...)
    method = ["ccd"]
    [[grid.cases]]
    method = ["discrete"]
    substeps = [1, 2, 4, 8]

    [plot]                     # optional: what --plot draws
    kind = "curve"             # "pareto": cost on x, y errors, one marker per method, the front
    x = "speed"                # curve only: a numeric parameter of the grid
    y = "missed_segments"      # a measurement, or a list of them (one panel each)
    by = "workload"            # optional: one chart per value of a parameter
    xscale = "log"             # optional: "linear" or "log" (pareto: log-log)

Parameters (each a list, a single value, or a table {range = [start, stop(, step)]},
{linspace = [first, last, count]} or {geomspace = [first, last, count]}):
  scene        a scene name or path, as `collisim render` takes (a scene of one world)
  workload     slow_gas, dense_gas, fast_gas, gravity_bounce (collisim.analysis.bench.workloads),
               barrier (one particle against a thin segment: analysis/sweep/workloads.py)
  method       discrete, ccd, pymunk             substeps     whole number >= 1
  broadphase   brute, sweep_prune, grid, kdtree, bvh
  fps, seconds number > 0                        restitution  in [0, 1]
  seed, n, speed, packing, phase   workloads only, where the generator takes them: seed and n
               (gravity_bounce's count) whole numbers; speed in radii per frame; packing in
               (0, 0.9); phase (barrier) in [0, 1]
A setting a job does not give is the scene's or workload's own.

Measurements (compare.measure's keys, and events): cost (wall seconds per simulated second,
after a warm-up of two frames), energy_drift, momentum_drift, max_overlap, outside_end,
outside_ever, missed_pairs, missed_segments, collisions, pair_collisions, wall_collisions,
segment_collisions, wall_pressure, position_error (against the ccd run of the same world: a
second simulation per job; empty, and a warning says why, for a world ccd refuses), warnings,
events. Default: all but position_error and warnings.

The table
---------
Columns: id, the settings (sorted), the measurements (sorted), error. A job's id is a hash
of its settings (spec.job_id): the same settings give the same id in any file and any run,
so running a sweep again skips the jobs already in its table (--fresh starts over), and the
table never holds a job twice. Rows come in the order jobs finish; a job that raises gets a
row with its error (one line) and empty measurements, and the sweep goes on.

Modules: spec.py (file, checks, grid, ids), workloads.py (what a sweep can name), job.py
(run_job: one job, in any process), runner.py (serial or Dask, the table), plot.py (charts),
cli.py (the command). Shipped sweeps: accuracy.toml (what `collisim bench accuracy` measures)
and tunnelling.toml (the tunnelling curve of discrete against ccd).
"""
from .job import run_job
from .runner import read_table, run_sweep
from .spec import Record, Sweep, expand, job_id, load_sweep, shipped_sweeps

__all__ = ["Record", "Sweep", "load_sweep", "expand", "job_id", "run_job", "run_sweep", "read_table",
           "shipped_sweeps"]
