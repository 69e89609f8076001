"""One job of a sweep: settings in, a row of plain numbers and strings out.

run_job is a pure function of its arguments (apart from the wall time it measures and the
files it is asked to write), so any process can run it: the serial loop, a Dask worker on this
machine or one on a cluster. It builds its world from the settings, simulates, measures and
writes its own video or trajectory file; only the row travels back, never frames.
"""
from __future__ import annotations

import time
import warnings
from pathlib import Path

import numpy as np

from ..compare import measure, one_line, run_method
from .spec import Record, job_id
from .workloads import make_workload

WARM_UP_FRAMES = 2      # run before the timed run, so compiling or loading kernels is not charged


def build_scene(settings: dict):
    """The single-world Scene a job simulates: its scene file or workload, with the settings'
    fps, seconds, broadphase and restitution applied (method and substeps go to run_method,
    which also knows pymunk)."""
    from ...model.scenefile import load_scene
    if "scene" in settings:
        scene = load_scene(settings["scene"])
        if scene.world is None:
            raise ValueError(f"scene '{settings['scene']}' is made of panels or chapters, not one world")
    else:
        scene = make_workload(settings["workload"], settings)
    return scene.with_options(fps=settings.get("fps"), seconds=settings.get("seconds"),
                              broadphase=settings.get("broadphase"), restitution=settings.get("restitution"))


def run_job(settings: dict, record: Record = Record()) -> dict:
    """Run one job: {"id", **settings, one key per record.measure, "error"}.

    A job that raises returns the same row with its measurements None and `error` set to one
    line (compare.one_line); it never raises, so one bad job does not stop a sweep."""
    row = {"id": job_id(settings), **settings}
    try:
        row.update(_measured(settings, record))
        row["error"] = ""
    except Exception as error:   # noqa: BLE001 - any failure of the job is a finding for its row
        row.update(dict.fromkeys(record.measure))
        row["error"] = one_line(error)
    return row


def _measured(settings: dict, record: Record) -> dict:
    scene = build_scene(settings)
    method = settings.get("method", scene.method)
    substeps = settings.get("substeps", scene.substeps)
    simulated = scene.frames / scene.fps
    with warnings.catch_warnings():   # ccd's event-budget warning is kept in traj.warnings
        warnings.simplefilter("ignore")
        if "cost" in record.measure:
            run_method(scene.replace(seconds=min(scene.seconds, WARM_UP_FRAMES / scene.fps)), method, substeps)
        start = time.perf_counter()
        traj = run_method(scene, method, substeps)
        cost = (time.perf_counter() - start) / simulated
        reference, refused = None, []
        if "position_error" in record.measure:   # the ccd run of the same world
            reference, refused = (traj, []) if method == "ccd" else _ccd_reference(scene)
    measured = measure(scene.world, traj, reference, record.horizon, cost)
    measured["events"] = len(traj.events)
    measured["warnings"] = "; ".join(measured["warnings"] + refused)
    if record.video or record.trajectory:
        _write_files(traj, scene, job_id(settings), record)
    return {key: plain(measured[key]) for key in record.measure}


def _ccd_reference(scene):
    """(the ccd run position_error compares with, [why there is none]): a world ccd refuses
    (polygons, gravity that differs between bodies) leaves position_error empty and says why, as
    compare does, instead of failing the job's other measurements."""
    try:
        return run_method(scene, "ccd", 1), []
    except ValueError as error:
        return None, [f"no position_error: {one_line(error)}"]


def _write_files(traj, scene, name: str, record: Record) -> None:
    folder = Path(record.folder or ".")
    folder.mkdir(parents=True, exist_ok=True)
    if record.trajectory:
        traj.save(folder / f"{name}.npz")
    if record.video:
        from ...pipeline import render
        render(traj, folder / f"{name}.mp4", settings=scene.render)


def plain(value):
    """A number, string or None that any process and a CSV file take as is."""
    if value is None or isinstance(value, str):
        return value
    if isinstance(value, (bool, np.bool_)):
        return int(value)
    if isinstance(value, (int, np.integer)):
        return int(value)
    return float(value)     # inf and nan stay: they are findings


def warm_up(settings: dict, record: Record) -> None:
    """Run the job on its first frames, measurements included, and forget it: compiles (or loads
    from numba's cache) every kernel the job's method, broad phase and world need."""
    short = dict(settings)
    try:
        scene = build_scene(settings)
        short["seconds"] = min(scene.seconds, WARM_UP_FRAMES / scene.fps)
    except Exception:   # noqa: BLE001 - the job itself will report it
        return
    run_job(short, Record(measure=record.measure, horizon=record.horizon))
