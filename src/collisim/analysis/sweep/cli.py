"""`collisim sweep FILE`: run a sweep file's grid of jobs into a CSV table, and chart it.

collisim/cli.py wires it in with add_sweep_parser(commands) and COMMANDS["sweep"] = cmd_sweep.
Bad input is a ValueError (one line, exit status 2 through collisim's main), raised before any
job runs.
"""
from __future__ import annotations

import signal
import sys
from pathlib import Path


def _workers(text: str) -> int:
    import argparse
    try:
        value = int(text)
    except ValueError:
        value = -1
    if value < 0:
        raise argparse.ArgumentTypeError(f"--workers must be a whole number >= 0, got '{text}'")
    return value


def add_sweep_parser(commands) -> None:
    """Add the `sweep` subcommand to collisim's subparsers (parser_class=OneLineParser)."""
    sweep = commands.add_parser("sweep", help="run a grid of simulations from a sweep file (.toml) serially "
                                              "or on Dask, one CSV row per job; charts with --plot")
    sweep.add_argument("file", metavar="FILE", help="a sweep file, or a shipped sweep's name (accuracy, tunnelling)")
    sweep.add_argument("--workers", type=_workers, metavar="N",
                       help="processes of a local Dask cluster (default: one per core); 0 runs the jobs one "
                            "after another in this process, without Dask")
    sweep.add_argument("--scheduler", metavar="ADDRESS",
                       help="run on an existing Dask cluster, e.g. tcp://10.0.0.5:8786, instead of a local one")
    sweep.add_argument("--out", type=Path, help="the CSV table (default renders/sweeps/<name>.csv)")
    sweep.add_argument("--fresh", action="store_true", help="start the table over instead of skipping the jobs "
                                                            "already in it")
    sweep.add_argument("--plot", action="store_true", help="also draw the sweep file's [plot] as PNG beside the table")
    sweep.add_argument("--no-progress", action="store_true", help="no progress bar")


def cmd_sweep(args) -> int:
    from .plot import plot_sweep
    from .runner import read_table, run_sweep
    from .spec import job_id, load_sweep

    sweep = load_sweep(args.file)
    if args.plot and not sweep.plot:
        raise ValueError(f"{sweep.path.name} has no [plot] table: nothing to draw")
    if args.workers is not None and args.scheduler is not None:
        raise ValueError("give either --workers (a cluster on this machine) or --scheduler (an existing one)")
    try:
        summary = run_sweep(sweep, args.out, workers=args.workers, scheduler=args.scheduler, fresh=args.fresh,
                            progress=not args.no_progress)
    except KeyboardInterrupt as interrupt:   # Ctrl-C, or SIGTERM/SIGHUP as collisim's main turns them
        signum = getattr(interrupt, "signum", signal.SIGINT)
        print(f"collisim: interrupted ({signal.Signals(signum).name}); every finished job is in the table, "
              f"run the same command to go on", file=sys.stderr)
        return 128 + signum
    if summary["ran"] or summary["skipped"] < summary["jobs"]:
        print(f"{summary['table']}: {summary['jobs']} jobs; {summary['ran']} ran {summary['where']}, "
              f"{summary['skipped']} were already in the table; {summary['errors']} failed"
              + (" (see the error column)" if summary["errors"] else ""))
    else:
        print(f"{summary['table']}: all {summary['jobs']} jobs were already in the table (--fresh runs them again)")
    if args.plot:
        ids = {job_id(job) for job in sweep.jobs}
        rows = [row for row in read_table(summary["table"]) if row["id"] in ids]
        for path in plot_sweep(rows, sweep.plot, summary["table"], sweep.name):
            print(f"{path}: {sweep.plot['kind']} chart")
    return 0
