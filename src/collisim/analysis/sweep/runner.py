"""Running a sweep's jobs, serially or on Dask, into a CSV table that survives interruption.

The table is the sweep's memory: each finished job is appended as one row and flushed at
once, so stopping a sweep (Ctrl-C, a lost connection, a killed job) loses only the jobs
still running; running the sweep again skips every job whose id is already in the table.
A job never appears twice: the table refuses an id it holds (a retried task, a duplicate).

Where jobs run:
  workers=0          a plain loop in this process, no Dask (for debugging, and the baseline);
  scheduler=ADDRESS  an existing Dask cluster (`dask scheduler` + `dask worker`, dask-jobqueue);
  otherwise          a LocalCluster on this machine: `workers` processes (default one per
                     core) of one thread each, NUMBA_NUM_THREADS=1 in them, so jobs do not
                     fight over cores.
Before Dask workers start, one tiny run of each (source, method, broad phase) of the pending
jobs runs here: numba compiles the kernels once and caches them on disk, and the workers load
them instead of each compiling the same kernels at the same time.
Dask re-runs the task of a lost worker (retries=2 covers a task that raises on a sick worker);
a job Dask gives up on is recorded with its error, like any job that fails.
"""
from __future__ import annotations

import csv
import os
import sys
from dataclasses import replace
from pathlib import Path

from ..compare import one_line
from .job import run_job, warm_up
from .spec import Sweep, job_id

DEFAULT_FOLDER = Path("renders/sweeps")
CONNECT_TIMEOUT = "20s"


class Table:
    """An append-only CSV table of job rows with a fixed header, one row per id."""

    def __init__(self, path: Path, columns: tuple, fresh: bool = False):
        self.path, self.columns = Path(path), tuple(columns)
        self.ids = set()
        if fresh:
            self.path.unlink(missing_ok=True)
        if self.path.exists():
            self._resume()
        self._file = open(self.path, "a", newline="", encoding="utf-8")
        self._writer = csv.DictWriter(self._file, fieldnames=self.columns, restval="", extrasaction="ignore")
        if not self._file.tell():
            self._writer.writeheader()
            self._file.flush()

    def _resume(self) -> None:
        """Read the ids already done; cut a last line left half-written by a killed run."""
        text = self.path.read_text(encoding="utf-8")
        if text and not text.endswith("\n"):
            text = text[:text.rfind("\n") + 1]
            self.path.write_text(text, encoding="utf-8")
        reader = csv.reader(text.splitlines())
        header = next(reader, None)
        if header is None:
            return
        if tuple(header) != self.columns:
            raise ValueError(f"{self.path} holds another sweep's columns (the file's grid or measure changed?); "
                             f"use --fresh to start it over, or --out for a new table")
        self.ids = {line[0] for line in reader if line}

    def append(self, row: dict) -> bool:
        """Write the row and flush it to disk; False (nothing written) if its id is in the table."""
        if row["id"] in self.ids:
            return False
        self._writer.writerow({key: "" if value is None else value for key, value in row.items()})
        self._file.flush()    # in the operating system's hands: a killed sweep keeps the row
        self.ids.add(row["id"])
        return True

    def close(self) -> None:
        self._file.close()


def read_table(path) -> list:
    """The rows of a sweep table as dicts of strings ('' for none)."""
    with open(path, newline="", encoding="utf-8") as file:
        return list(csv.DictReader(file))


def default_table(sweep: Sweep) -> Path:
    return DEFAULT_FOLDER / f"{sweep.name}.csv"


def run_sweep(sweep: Sweep, out=None, *, workers=None, scheduler=None, fresh: bool = False,
              progress: bool = True, timeout=None) -> dict:
    """Run the sweep's jobs that are not in the table yet; append each row as it finishes.

    out: the CSV table (default renders/sweeps/<name>.csv); videos and trajectories go to the
    folder of the same name beside it. workers: 0 runs serially here, N a LocalCluster of N
    processes (default os.cpu_count()); scheduler: the address of a running Dask scheduler.
    timeout: seconds to wait for the whole sweep on Dask (None: no limit).
    Returns {"table", "jobs", "ran", "skipped", "errors", "where"}.
    """
    from ...io.writers import check_writable
    from tqdm import tqdm

    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 0):
        raise ValueError(f"workers must be a whole number >= 0, got {workers!r}")
    if scheduler is not None and workers is not None:
        raise ValueError("give either --workers (a cluster on this machine) or --scheduler (an existing one)")
    out = Path(out) if out is not None else default_table(sweep)
    check_writable(out.parent)
    record = sweep.record
    if record.video or record.trajectory:
        record = replace(record, folder=str((out.parent / out.stem).resolve()))
    table = Table(out, sweep.columns, fresh=fresh)
    pending = [job for job in sweep.jobs if job_id(job) not in table.ids]
    summary = dict(table=out, jobs=len(sweep.jobs), ran=0, skipped=len(sweep.jobs) - len(pending), errors=0,
                   where="")
    bar = tqdm(total=len(sweep.jobs), initial=summary["skipped"], file=sys.stderr, disable=not progress,
               desc=sweep.name, unit="job")

    def finished(row: dict) -> None:
        if table.append(row):
            summary["ran"] += 1
            summary["errors"] += bool(row.get("error"))
        bar.update()
    try:
        if pending and workers == 0:
            summary["where"] = "serially, in this process"
            for job in pending:
                finished(run_job(job, record))
        elif pending:
            summary["where"] = run_on_dask(pending, record, finished, workers, scheduler, timeout)
    finally:
        bar.close()
        table.close()
    return summary


def run_on_dask(pending: list, record, finished, workers=None, scheduler=None, timeout=None) -> str:
    """Submit every pending job to Dask and hand each row to `finished` as it completes.
    Returns where the jobs ran, in words."""
    import logging

    from distributed import Client, LocalCluster, as_completed

    cluster = None
    try:
        if scheduler is not None:   # connect first: an unreachable scheduler is reported at once
            try:
                client = Client(scheduler, timeout=CONNECT_TIMEOUT)
            except (OSError, TimeoutError, ValueError) as error:
                raise ValueError(f"cannot reach the Dask scheduler at {scheduler}: {one_line(error)}") from None
            where = f"on the Dask cluster at {scheduler}"
        else:
            _warm_up(pending, record)   # before the workers start, so they load what it compiled
            count = workers or os.cpu_count() or 1
            try:
                cluster = LocalCluster(n_workers=count, threads_per_worker=1, processes=True, host="127.0.0.1",
                                       dashboard_address=None, silence_logs=logging.CRITICAL,
                                       env={"NUMBA_NUM_THREADS": "1"})
            except Exception as error:   # noqa: BLE001 - e.g. a script without `if __name__ == "__main__":`
                raise ValueError(f"could not start a local Dask cluster: {one_line(error)}") from None
            client = Client(cluster)
            where = f"on a local Dask cluster of {count} worker{'s' * (count != 1)}"
        try:
            if cluster is None:   # workers sharing this file system load what it compiles
                _warm_up(pending, record)
            futures = {client.submit(run_job, job, record, retries=2, pure=False): job for job in pending}
            try:
                for future in _completed(as_completed, futures, timeout):
                    job = futures.pop(future)
                    try:
                        row = future.result()
                    except Exception as error:   # noqa: BLE001 - Dask gave up on it (e.g. KilledWorker)
                        row = {"id": job_id(job), **job, **dict.fromkeys(record.measure), "error": one_line(error)}
                    future.release()
                    finished(row)
            finally:
                if futures:   # interrupted: stop what is still queued
                    client.cancel(list(futures))
        finally:
            client.close(timeout=10)
    finally:
        if cluster is not None:
            cluster.close(timeout=20)
    return where


def _warm_up(pending: list, record) -> None:
    """One tiny run of each (source, method, broad phase) here: numba compiles the kernels once
    and caches them on disk, and the workers load them instead of each compiling them at once."""
    warmed = set()
    for job in pending:
        key = (job.get("scene"), job.get("workload"), job.get("method"), job.get("broadphase"))
        if key not in warmed:
            warmed.add(key)
            warm_up(job, record)


def _completed(as_completed, futures, timeout):
    """as_completed, with its timeout reported in the product's words."""
    try:
        yield from as_completed(futures, timeout=timeout)
    except TimeoutError:
        raise ValueError(f"the sweep did not finish within {timeout:g} s; the finished jobs are in the table, "
                         f"run it again to go on") from None
