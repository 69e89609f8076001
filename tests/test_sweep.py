"""collisim sweep: sweep files, the grid, one job, and the same table serially, on a local Dask
cluster and on a cluster of separate processes; lost workers, interrupted sweeps, failing jobs
and bad files. Jobs are tiny (0.1 s, a few particles); every Dask call has a timeout."""
import csv
import os
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest

import collisim
from collisim.analysis.bench import accuracy
from collisim.analysis.sweep import Record, expand, job_id, load_sweep, read_table, run_job, run_sweep
from collisim.analysis.sweep import runner
from collisim.analysis.sweep.spec import MEASUREMENTS

ROOT = Path(__file__).resolve().parents[1]
DASK_TIMEOUT = 180      # seconds for a whole sweep on Dask: ample, but a hang ends

TINY = """
name = "tiny"
measure = ["cost", "energy_drift", "max_overlap", "missed_pairs", "collisions", "events", "position_error",
           "warnings"]

[grid]
workload = ["gravity_bounce"]
n = [4]
seconds = [0.1]
seed = [1, 2]

[[grid.cases]]
method = ["ccd"]

[[grid.cases]]
method = ["discrete"]
substeps = [1, 4]

[[grid.cases]]
method = ["pymunk"]

[plot]
kind = "pareto"
y = ["energy_drift", "max_overlap"]
"""


def write(folder: Path, text: str, name: str = "tiny.toml") -> Path:
    path = folder / name
    path.write_text(textwrap.dedent(text))
    return path


def sweep_cli(*argv):
    """`collisim sweep ARGV` through collisim's own main (one line and status 2 on bad input),
    with the sweep command added to its parser if collisim/cli.py does not have it yet."""
    import collisim.cli as cli
    from collisim.analysis.sweep.cli import add_sweep_parser, cmd_sweep
    if "sweep" in cli.COMMANDS:
        return cli.main(["sweep", *map(str, argv)])
    original = cli.build_parser

    def build_parser():
        parser = original()
        add_sweep_parser(next(a for a in parser._actions if a.dest == "command"))
        return parser
    cli.build_parser, cli.COMMANDS["sweep"] = build_parser, cmd_sweep
    try:
        return cli.main(["sweep", *map(str, argv)])
    finally:
        cli.build_parser = original
        del cli.COMMANDS["sweep"]


def table(path: Path, drop=("cost",)) -> list:
    """The table's rows sorted by id, without the timing columns."""
    rows = [{k: v for k, v in row.items() if k not in drop} for row in read_table(path)]
    return sorted(rows, key=lambda row: row["id"])


def header(path: Path) -> list:
    with open(path, newline="") as file:
        return next(csv.reader(file))


# --- the file and the grid ----------------------------------------------------------------------

def test_grid_expands_to_the_product_times_the_cases_with_stable_ids(tmp_path):
    sweep = load_sweep(write(tmp_path, TINY))
    assert len(sweep.jobs) == 2 * (1 + 2 + 1)
    assert {(j["method"], j.get("substeps")) for j in sweep.jobs} == {("ccd", None), ("discrete", 1),
                                                                     ("discrete", 4), ("pymunk", None)}
    ids = [job_id(job) for job in sweep.jobs]
    assert len(set(ids)) == len(ids) and all(len(i) == 12 for i in ids)
    job = dict(sweep.jobs[0])
    assert job_id(dict(reversed(list(job.items())))) == job_id(job)           # key order does not matter
    assert job_id({**job, "seconds": 0.1}) == job_id(job)
    assert job_id({"workload": "barrier", "fps": 60}) == job_id({"workload": "barrier", "fps": 60.0})
    assert job_id({**job, "seed": 3}) != job_id(job)
    assert sweep.columns == ("id", "method", "n", "seconds", "seed", "substeps", "workload", "collisions", "cost",
                             "energy_drift", "events", "max_overlap", "missed_pairs", "position_error", "warnings",
                             "error")


def test_value_tables_and_single_values(tmp_path):
    jobs = expand({"workload": "barrier", "speed": {"geomspace": [1, 100, 3]}, "phase": {"linspace": [0, 1, 5]},
                   "method": "ccd"})
    assert sorted({j["speed"] for j in jobs}) == [1.0, 10.0, 100.0]
    assert sorted({j["phase"] for j in jobs}) == [0.0, 0.25, 0.5, 0.75, 1.0]
    seeds = expand({"workload": "slow_gas", "seed": {"range": [0, 10, 3]}})
    assert [j["seed"] for j in seeds] == [0, 3, 6, 9]


def test_shipped_sweeps_are_found_by_name_and_reproduce_bench_accuracy():
    sweep = load_sweep("accuracy")
    configurations = {(j["workload"], j["method"], j.get("substeps", 1)) for j in sweep.jobs}
    expected = {(w, e, k) for w in ("slow_gas", "dense_gas", "fast_gas", "gravity_bounce")
                for e, k in accuracy.configurations()}
    assert configurations == expected and len(sweep.jobs) == len(expected)
    assert {j["broadphase"] for j in sweep.jobs} == {accuracy.BROADPHASE}
    assert sweep.record.horizon == accuracy.HORIZON
    tunnelling = load_sweep("tunnelling")
    assert len(tunnelling.jobs) == 1000 and {j["method"] for j in tunnelling.jobs} == {"discrete", "ccd"}


def test_measurement_names_are_compare_measure_keys_and_events():
    world = collisim.World([[2.0, 5.0], [8.0, 5.0]], [[3.0, 0.0], [-3.0, 0.0]], 0.6)
    traj = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=0.05))
    from collisim.analysis.compare import measure
    assert set(MEASUREMENTS) == set(measure(world, traj, traj, 0.0)) | {"events"}


# --- one job ------------------------------------------------------------------------------------

def test_a_job_is_a_row_of_plain_values_with_its_settings():
    settings = {"workload": "gravity_bounce", "n": 3, "seconds": 0.1, "method": "discrete", "substeps": 2}
    row = run_job(settings, Record(measure=("cost", "collisions", "position_error", "events", "warnings")))
    assert row["error"] == "" and row["id"] == job_id(settings)
    assert {k: row[k] for k in settings} == settings
    assert row["cost"] > 0 and row["position_error"] >= 0 and row["warnings"] == ""
    assert all(isinstance(v, (int, float, str)) for v in row.values())


def test_a_world_ccd_refuses_leaves_only_position_error_empty_and_says_why():
    # polygons: position_error has no ccd run to compare with; the job's other measurements stand
    record = Record(measure=("max_overlap", "collisions", "position_error", "warnings"))
    for method in ("discrete", "pymunk"):
        row = run_job({"scene": "polygons", "seconds": 1.0, "method": method}, record)
        assert row["error"] == "" and row["position_error"] is None
        assert row["collisions"] > 0 and row["max_overlap"] >= 0.0
        assert row["warnings"].startswith("no position_error: method ccd covers circles")
    assert run_job({"scene": "polygons", "seconds": 0.1, "method": "ccd"}, record)["error"].startswith("method ccd")


def test_a_job_that_raises_returns_its_error_in_one_line():
    row = run_job({"workload": "slow_gas", "packing": 0.85, "seconds": 0.1})
    assert row["error"].startswith("250 circles") and "\n" not in row["error"]   # collisim's refusal, in its words
    assert all(row[m] is None for m in Record().measure)


def test_barrier_tunnels_under_discrete_and_never_under_ccd():
    record = Record(measure=("missed_segments", "segment_collisions"))
    fast = {"workload": "barrier", "speed": 8.0, "phase": 0.5}
    assert run_job({**fast, "method": "discrete"}, record)["missed_segments"] == 1
    assert run_job({**fast, "method": "ccd"}, record)["missed_segments"] == 0
    slow = run_job({**fast, "speed": 0.5, "method": "discrete"}, record)
    assert slow["missed_segments"] == 0 and slow["segment_collisions"] == 1


# --- running: serial, local cluster, separate processes -----------------------------------------

@pytest.fixture(scope="module")
def serial_table(tmp_path_factory):
    folder = tmp_path_factory.mktemp("serial")
    assert sweep_cli(write(folder, TINY), "--workers", "0", "--out", folder / "tiny.csv", "--no-progress") == 0
    return folder / "tiny.csv"


def test_serial_sweep_writes_the_canonical_table(serial_table):
    rows = read_table(serial_table)
    assert header(serial_table) == list(load_sweep(serial_table.parent / "tiny.toml").columns)
    assert len(rows) == 8 and all(row["error"] == "" for row in rows)
    ccd = [row for row in rows if row["method"] == "ccd"]
    assert all(float(row["position_error"]) == 0.0 and float(row["max_overlap"]) == 0.0 for row in ccd)


def test_local_cluster_gives_the_serial_table(serial_table, tmp_path):
    sweep = load_sweep(serial_table.parent / "tiny.toml")
    summary = run_sweep(sweep, tmp_path / "tiny.csv", workers=2, progress=False, timeout=DASK_TIMEOUT)
    assert summary["ran"] == 8 and summary["errors"] == 0 and "2 workers" in summary["where"]
    assert header(tmp_path / "tiny.csv") == header(serial_table)
    assert table(tmp_path / "tiny.csv") == table(serial_table)


@pytest.fixture
def dask_processes(tmp_path):
    """A scheduler and two workers, each its own process, on 127.0.0.1: the scheduler's address."""
    from distributed import Client
    scheduler_file = tmp_path / "scheduler.json"
    env = {**os.environ, "NUMBA_NUM_THREADS": "1"}
    common = ["--host", "127.0.0.1", "--no-dashboard"]
    processes = [subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_scheduler", "--port", "0",
                                   "--scheduler-file", scheduler_file, *common], cwd=ROOT, env=env,
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)]
    try:
        deadline = time.monotonic() + 60
        while not scheduler_file.exists() and time.monotonic() < deadline:
            time.sleep(0.2)
        for _ in range(2):
            processes.append(subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", "--nthreads", "1",
                                               "--scheduler-file", scheduler_file, "--death-timeout", "60", *common],
                                              cwd=ROOT, env=env, stdout=subprocess.DEVNULL,
                                              stderr=subprocess.DEVNULL))
        with Client(scheduler_file=str(scheduler_file), timeout="30s") as client:
            client.wait_for_workers(2, timeout=90)
            address = client.scheduler.address
        yield address
    finally:
        for process in reversed(processes):
            process.terminate()
        for process in reversed(processes):
            try:
                process.wait(timeout=30)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait(timeout=10)


@pytest.mark.slow
def test_cluster_of_separate_processes_gives_the_serial_table(serial_table, tmp_path, dask_processes):
    sweep = load_sweep(serial_table.parent / "tiny.toml")
    summary = run_sweep(sweep, tmp_path / "tiny.csv", scheduler=dask_processes, progress=False,
                        timeout=DASK_TIMEOUT)
    assert summary["ran"] == 8 and summary["errors"] == 0 and dask_processes in summary["where"]
    assert table(tmp_path / "tiny.csv") == table(serial_table)


KILLER = '''
"""Two particles; the first time it is built inside a Dask worker, it kills that worker."""
import os
import signal
import time

import collisim

def scene():
    try:
        from distributed import get_worker
        get_worker()
    except (ImportError, ValueError):
        pass
    else:
        import numba
        with open({marker!r} + ".threads", "a") as file:   # what the sweep set in its workers
            file.write(f"{{os.environ.get('NUMBA_NUM_THREADS')}} {{numba.config.NUMBA_NUM_THREADS}}\\n")
        time.sleep(0.3)                    # the other worker is busy meanwhile
        try:
            os.close(os.open({marker!r}, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
        except FileExistsError:
            pass
        else:
            os.kill(os.getpid(), signal.SIGKILL)
    world = collisim.World([[2.0, 5.0], [8.0, 5.0]], [[3.0, 0.0], [-3.0, 0.0]], 0.6)
    return collisim.Scene(world=world, fps=60, seconds=0.1)
'''


def test_a_killed_worker_loses_no_job_and_doubles_none(tmp_path):
    marker = tmp_path / "killed"
    scene = tmp_path / "killer.py"
    scene.write_text(KILLER.format(marker=str(marker)))
    path = write(tmp_path, f"""
        measure = ["collisions", "events"]
        [grid]
        scene = ["{scene}"]
        method = ["discrete", "ccd"]
        seconds = [0.05, 0.1, 0.15]
        """)
    summary = run_sweep(load_sweep(path), tmp_path / "killer.csv", workers=2, progress=False,
                        timeout=DASK_TIMEOUT)
    rows = read_table(tmp_path / "killer.csv")
    assert marker.exists()                                     # a worker was killed mid-sweep
    assert set(Path(f"{marker}.threads").read_text().splitlines()) == {"1 1"}
    assert summary["ran"] == 6 and len(rows) == 6 and len({row["id"] for row in rows}) == 6
    assert all(row["error"] == "" for row in rows)


# --- interrupted, re-run, failing jobs ----------------------------------------------------------

def test_rerun_runs_only_the_jobs_missing_from_the_table(serial_table, tmp_path, monkeypatch):
    out = tmp_path / "tiny.csv"
    lines = serial_table.read_text().splitlines(keepends=True)
    out.write_text("".join(lines[:4]) + lines[4][:20])           # 3 rows, and a row cut by a kill
    ran = []
    monkeypatch.setattr(runner, "run_job", lambda job, record: ran.append(job) or run_job(job, record))
    assert sweep_cli(serial_table.parent / "tiny.toml", "--workers", "0", "--out", out, "--no-progress") == 0
    assert len(ran) == 5
    assert table(out) == table(serial_table)                      # each job once, the cut row run again
    assert sweep_cli(serial_table.parent / "tiny.toml", "--workers", "0", "--out", out, "--no-progress") == 0
    assert len(ran) == 5                                          # all done: nothing runs
    assert sweep_cli(serial_table.parent / "tiny.toml", "--workers", "0", "--out", out, "--fresh",
                     "--no-progress") == 0
    assert len(ran) == 13 and len(read_table(out)) == 8


def test_the_table_never_holds_an_id_twice(tmp_path):
    table_ = runner.Table(tmp_path / "t.csv", ("id", "x", "error"))
    assert table_.append({"id": "a", "x": 1, "error": ""})
    assert not table_.append({"id": "a", "x": 2, "error": ""})
    table_.close()
    assert [row["x"] for row in read_table(tmp_path / "t.csv")] == ["1"]


def test_a_failing_job_is_recorded_and_the_sweep_goes_on(tmp_path, capsys):
    path = write(tmp_path, """
        measure = ["collisions"]
        [grid]
        workload = ["slow_gas"]
        n = [20]
        packing = [0.05, 0.85]
        seconds = [0.1]
        """)
    assert sweep_cli(path, "--workers", "0", "--out", tmp_path / "t.csv", "--no-progress") == 0
    rows = {row["packing"]: row for row in read_table(tmp_path / "t.csv")}
    assert rows["0.85"]["error"].startswith("20 circles") and rows["0.85"]["collisions"] == ""
    assert rows["0.05"]["error"] == "" and int(rows["0.05"]["collisions"]) >= 0
    assert "1 failed" in capsys.readouterr().out


def test_files_per_job_and_plots(tmp_path, capsys):
    path = write(tmp_path, """
        measure = ["missed_segments", "cost"]
        video = true
        trajectory = true
        [grid]
        workload = ["barrier"]
        method = ["discrete", "ccd"]
        speed = [0.5, 8.0]
        phase = [0.25, 0.75]
        [plot]
        kind = "curve"
        x = "speed"
        y = "missed_segments"
        by = "method"
        """)
    out = tmp_path / "out" / "barrier.csv"
    assert sweep_cli(path, "--workers", "0", "--out", out, "--plot", "--no-progress") == 0
    rows = read_table(out)
    assert len(rows) == 8
    ids = {row["id"] for row in rows}
    assert {p.name for p in (tmp_path / "out" / "barrier").iterdir()} == \
        {f"{i}.mp4" for i in ids} | {f"{i}.npz" for i in ids}
    saved = collisim.load_trajectory(tmp_path / "out" / "barrier" / f"{rows[0]['id']}.npz")
    assert saved.frames == 8
    assert sorted(p.name for p in out.parent.glob("*.png")) == ["barrier_ccd.png", "barrier_discrete.png"]
    capsys.readouterr()
    pareto = write(tmp_path, TINY, "pareto.toml")
    assert sweep_cli(pareto, "--workers", "0", "--out", tmp_path / "p.csv", "--plot", "--no-progress") == 0
    assert (tmp_path / "p.png").stat().st_size > 10_000


# --- bad sweep files ------------------------------------------------------------------------------

GOOD_GRID = '[grid]\nworkload = ["gravity_bounce"]\nseconds = [0.1]\n'
BAD_FILES = {
    "unknown parameter": ('[grid]\nworkload = ["gravity_bounce"]\nsubstep = [1]\n', "unknown parameter 'substep'"),
    "unknown scene": ('[grid]\nscene = ["no_such_scene"]\n', "unknown scene 'no_such_scene'"),
    "unknown workload": ('[grid]\nworkload = ["liquid"]\n', "unknown workload 'liquid'"),
    "empty list": (GOOD_GRID + "seed = []\n", "parameter 'seed' has an empty list"),
    "substeps a word": (GOOD_GRID + 'substeps = "four"\n', "substeps must be a whole number >= 1, got 'four'"),
    "restitution above 1": (GOOD_GRID + "restitution = 2\n", "restitution must be a finite number in [0, 1], got 2"),
    "invalid TOML": ("[grid\nworkload = 1\n", "is not valid TOML"),
    "unknown measurement": ('measure = ["speed"]\n' + GOOD_GRID, "unknown measurement 'speed'"),
    "parameter the workload lacks": (GOOD_GRID + "packing = [0.1]\n", "'gravity_bounce' takes no parameter 'packing'"),
    "scene of panels": ('[grid]\nscene = ["tunneling"]\n', "made of panels or chapters"),
    "no source": ('[grid]\nmethod = ["ccd"]\n', "needs exactly one of scene"),
    "values beyond the limit": ('[grid]\nworkload = ["barrier"]\nspeed = { linspace = [0.5, 40.0, 100000000] }\n',
                                "100 000 000 values of speed; a sweep file runs at most 1 000 000 jobs"),
    "grid beyond the limit": ('[grid]\nworkload = ["barrier"]\nmethod = ["discrete", "ccd"]\n'
                              'speed = { linspace = [0.5, 40.0, 1000] }\nphase = { linspace = [0.1, 0.9, 1000] }\n',
                              "2 000 000 jobs in the grid; a sweep file runs at most 1 000 000 jobs"),
}


@pytest.mark.parametrize("case", [*BAD_FILES, "missing file", "folder"])
def test_a_bad_sweep_file_is_one_line_and_nothing_runs(tmp_path, capsys, monkeypatch, case):
    monkeypatch.setattr(runner, "run_job", lambda *a: pytest.fail("a job ran"))
    if case in BAD_FILES:
        path = write(tmp_path, BAD_FILES[case][0], "bad.toml")
    else:
        path = tmp_path / ("missing.toml" if case == "missing file" else "sweeps.toml")
        if case == "folder":
            path.mkdir()
    status = sweep_cli(path, "--workers", "0", "--out", tmp_path / "out" / "bad.csv")
    err = capsys.readouterr().err
    assert status == 2
    assert err.count("\n") == 1 and err.startswith("collisim: error: ") and "Traceback" not in err
    expected = {"missing file": "sweep file not found", "folder": "sweeps.toml is a folder, not a file"}
    assert (BAD_FILES[case][1] if case in BAD_FILES else expected[case]) in err
    assert not (tmp_path / "out").exists()


def test_plot_asking_for_an_unmeasured_column_is_refused(tmp_path, capsys):
    path = write(tmp_path, 'measure = ["collisions"]\n' + GOOD_GRID + '[plot]\nkind = "pareto"\ny = "collisions"\n')
    assert sweep_cli(path, "--workers", "0", "--out", tmp_path / "out" / "t.csv") == 2
    assert "pareto plot has cost on x" in capsys.readouterr().err
    assert not (tmp_path / "out").exists()


@pytest.mark.skipif("sweep" not in __import__("collisim.cli").cli.COMMANDS,
                    reason="collisim/cli.py does not wire in the sweep command yet")
def test_python_m_collisim_sweep(cli, tmp_path):
    path = write(tmp_path, TINY)
    result = cli("sweep", path, "--workers", "0", "--out", tmp_path / "t.csv", "--no-progress")
    assert result.returncode == 0, result.stderr
    assert len(read_table(tmp_path / "t.csv")) == 8
    result = cli("sweep", tmp_path / "missing.toml")
    assert result.returncode == 2 and result.stderr.count("\n") == 1


def test_usage_mistakes_are_one_line(tmp_path, capsys):
    with pytest.raises(SystemExit) as exit_:
        sweep_cli("accuracy", "--workers", "-1")
    assert exit_.value.code == 2 and capsys.readouterr().err.count("\n") == 1
    assert sweep_cli("no_such_sweep") == 2
    assert "unknown sweep 'no_such_sweep'" in capsys.readouterr().err
    assert sweep_cli("accuracy", "--workers", "2", "--scheduler", "tcp://127.0.0.1:1", "--out", tmp_path / "a.csv") == 2
    assert "either --workers" in capsys.readouterr().err
