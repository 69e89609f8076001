"""Reading a sweep file: check every value, expand the grid into jobs, give each a stable id.

The schema is in this package's docstring (collisim/analysis/sweep/__init__.py). Everything a
job could trip over is checked here, before any job runs, and reported as one ValueError line
that starts with the file's name.
"""
from __future__ import annotations

import hashlib
import itertools
import json
import math
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path

from ...broadphase import NAMES as BROAD_PHASES
from ...core.checks import is_file, missing_file
from .workloads import WORKLOADS, takes

if sys.version_info >= (3, 11):
    import tomllib
else:   # pragma: no cover - Python 3.10
    import tomli as tomllib

SHIPPED = Path(__file__).resolve().parent          # the sweep files installed with the package
METHODS = ("discrete", "ccd", "pymunk")
SOURCES = ("scene", "workload")
WORKLOAD_PARAMETERS = ("seed", "n", "speed", "packing", "phase")
# The keys of collisim.analysis.compare.measure's result, plus `events` (every impact logged).
MEASUREMENTS = ("cost", "energy_drift", "momentum_drift", "max_overlap", "outside_end", "outside_ever",
                "missed_pairs", "missed_segments", "collisions", "pair_collisions", "wall_collisions",
                "segment_collisions", "wall_pressure", "position_error", "warnings", "events")
DEFAULT_MEASURE = tuple(m for m in MEASUREMENTS if m not in ("position_error", "warnings"))
HORIZON = 0.25          # seconds: when position_error compares with ccd (as collisim compare)
MAX_JOBS = 1_000_000    # a sweep file's grid: more jobs are refused before any is made (split the file)
TOP_LEVEL = ("name", "description", "measure", "horizon", "video", "trajectory", "grid", "plot")
PLOT_KEYS = ("kind", "x", "y", "by", "xscale", "yscale", "title")


@dataclass(frozen=True)
class Record:
    """What each job records besides its settings: measurements (names from MEASUREMENTS), the
    horizon of position_error, and whether it writes <folder>/<id>.mp4 and <id>.npz."""
    measure: tuple = DEFAULT_MEASURE
    horizon: float = HORIZON
    video: bool = False
    trajectory: bool = False
    folder: str = ""


@dataclass(frozen=True)
class Sweep:
    """A checked sweep file: its jobs (settings dicts, grid order, no duplicates) and how to
    record and chart them. columns is the table's canonical header."""
    name: str
    path: Path
    jobs: tuple
    record: Record
    plot: dict = field(default_factory=dict)
    description: str = ""

    @property
    def settings_columns(self) -> tuple:
        return tuple(sorted({key for job in self.jobs for key in job}))

    @property
    def columns(self) -> tuple:
        return ("id", *self.settings_columns, *sorted(self.record.measure), "error")


def job_id(settings: dict) -> str:
    """12 hex digits of a hash of the canonical settings: the same job always gets the same id,
    whatever order or number type (1 or 1.0) the file used."""
    canonical = json.dumps(canonical_settings(settings), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(canonical.encode()).hexdigest()[:12]


def canonical_settings(settings: dict) -> dict:
    return {key: float(value) if key in FLOATS else value for key, value in settings.items() if key != "id"}


# --- parameters ---------------------------------------------------------------------------------

def _whole(minimum: int):
    def check(name, value):
        if isinstance(value, float) and value.is_integer():
            value = int(value)
        if isinstance(value, bool) or not isinstance(value, int) or value < minimum:
            raise ValueError(f"{name} must be a whole number >= {minimum}, got {value!r}")
        return value
    return check


def _number(low: float, high: float = math.inf, *, low_open: bool = True, high_open: bool = False):
    def check(name, value):
        ok = not isinstance(value, bool) and isinstance(value, (int, float)) and math.isfinite(value) \
            and (value > low if low_open else value >= low) and (value < high if high_open else value <= high)
        if not ok:
            left, right = "(" if low_open else "[", ")" if high_open or high == math.inf else "]"
            high_text = "inf" if high == math.inf else f"{high:g}"
            raise ValueError(f"{name} must be a finite number in {left}{low:g}, {high_text}{right}, got {value!r}")
        return float(value)
    return check


def _choice(choices):
    def check(name, value):
        if value not in choices:
            raise ValueError(f"unknown {name} {value!r}; choose from: {', '.join(choices)}")
        return value
    return check


def _text(name, value):
    if not isinstance(value, str) or not value:
        raise ValueError(f"{name} must be a name or a path (a string), got {value!r}")
    return value


PARAMETERS = {   # name -> check(name, value): the normalized value, or ValueError
    "scene": _text, "workload": _choice(tuple(WORKLOADS)),
    "method": _choice(METHODS), "substeps": _whole(1), "broadphase": _choice(("auto",) + tuple(BROAD_PHASES)),
    "fps": _number(0.0), "seconds": _number(0.0), "restitution": _number(0.0, 1.0, low_open=False),
    "seed": _whole(0), "n": _whole(1), "speed": _number(0.0), "packing": _number(0.0, 0.9, high_open=True),
    "phase": _number(0.0, 1.0, low_open=False),
}
FLOATS = ("fps", "seconds", "restitution", "speed", "packing", "phase")
NUMERIC = FLOATS + ("substeps", "seed", "n")


def _values(name: str, raw) -> list:
    """A parameter's list of values: a list, one value, or a range table."""
    if isinstance(raw, dict):
        raw = _range(name, raw)
    elif not isinstance(raw, list):
        raw = [raw]
    if not raw:
        raise ValueError(f"parameter '{name}' has an empty list: the grid would have no jobs")
    return list(dict.fromkeys(PARAMETERS[name](name, value) for value in raw))


def _range(name: str, table: dict) -> list:
    """{range = [start, stop(, step)]} (whole numbers, stop excluded, as Python's range),
    {linspace = [first, last, count]} or {geomspace = [first, last, count]} (as numpy's)."""
    if len(table) != 1 or next(iter(table)) not in ("range", "linspace", "geomspace"):
        raise ValueError(f"{name}: a table of values must be one of {{range = [start, stop, step]}}, "
                         f"{{linspace = [first, last, count]}}, {{geomspace = [first, last, count]}}")
    kind, args = next(iter(table.items()))
    numbers = isinstance(args, list) and all(isinstance(a, (int, float)) and not isinstance(a, bool) for a in args)
    if kind == "range":
        if not numbers or len(args) not in (2, 3) or not all(isinstance(a, int) for a in args) or 0 in args[2:]:
            raise ValueError(f"{name}: range takes [start, stop] or [start, stop, step], whole numbers, step != 0")
        _require_few(f"values of {name}", len(range(*args)))
        return list(range(*args))
    if not numbers or len(args) != 3 or not isinstance(args[2], int) or args[2] < 1 \
            or not all(math.isfinite(a) for a in args) or (kind == "geomspace" and min(args[:2]) <= 0):
        raise ValueError(f"{name}: {kind} takes [first, last, count], count a whole number >= 1"
                         + (", first and last > 0" if kind == "geomspace" else ""))
    _require_few(f"values of {name}", args[2])
    import numpy as np
    spaced = (np.geomspace if kind == "geomspace" else np.linspace)(args[0], args[1], args[2])
    return [float(f"{value:.12g}") for value in spaced]   # 12 digits: clean ids and tables


def _require_few(what: str, count: int) -> None:
    """Refuse more than MAX_JOBS of `what` ("values", a parameter's; "jobs", a grid's) before
    they are made: a grid of a trillion jobs filled the memory and never began."""
    if count > MAX_JOBS:
        raise ValueError(f"{count:,} {what}; a sweep file runs at most {MAX_JOBS:,} jobs (split the grid into "
                         f"several files)".replace(",", " "))


# --- the file -----------------------------------------------------------------------------------

def find_sweep_file(text) -> Path:
    """A path to a sweep file, or the name of a shipped one (`accuracy`)."""
    path = Path(str(text))
    if is_file(path):
        return path
    if path.suffix == "" and len(path.parts) == 1:
        shipped = shipped_sweeps()
        if str(text) in shipped:
            return shipped[str(text)]
        raise ValueError(f"unknown sweep '{text}': not a file, nor a shipped sweep ({', '.join(shipped)})")
    raise ValueError(missing_file("sweep file", str(text)))


def shipped_sweeps() -> dict:
    """name -> path of the sweep files installed with collisim."""
    return {path.stem: path for path in sorted(SHIPPED.glob("*.toml"))}


def load_sweep(file) -> Sweep:
    """Read and check a sweep file (a path, or a shipped sweep's name): a Sweep, or ValueError."""
    path = find_sweep_file(file)
    try:
        data = tomllib.loads(path.read_text(encoding="utf-8"))
    except OSError as error:
        raise ValueError(f"cannot read sweep file {path}: {error.strerror or error}") from None
    except UnicodeDecodeError:
        raise ValueError(f"{path.name} is not valid TOML: not UTF-8 text") from None
    except tomllib.TOMLDecodeError as error:
        raise ValueError(f"{path.name} is not valid TOML: {error}") from None
    try:
        return parse_sweep(data, path)
    except ValueError as error:
        raise ValueError(f"{path.name}: {error}") from None


def parse_sweep(data: dict, path: Path) -> Sweep:
    unknown = [key for key in data if key not in TOP_LEVEL]
    if unknown:
        raise ValueError(f"unknown key '{unknown[0]}'; a sweep file has: {', '.join(TOP_LEVEL)}")
    name = data.get("name", path.stem)
    if not isinstance(name, str) or not re.fullmatch(r"[A-Za-z0-9][A-Za-z0-9_.-]*", name):
        raise ValueError(f"name must be letters, digits, '_', '.' or '-' (it names the table), got {name!r}")
    if "grid" not in data or not isinstance(data["grid"], dict):
        raise ValueError("no [grid] table: which scenes or workloads to run, and the parameters to vary")
    record = _record(data)
    jobs = expand(data["grid"])
    plot = check_plot(data.get("plot"), jobs, record) if "plot" in data else {}
    description = data.get("description", "")
    if not isinstance(description, str):
        raise ValueError("description must be a string")
    return Sweep(name=name, path=path, jobs=tuple(jobs), record=record, plot=plot, description=description)


def _record(data: dict) -> Record:
    measure = data.get("measure", list(DEFAULT_MEASURE))
    if not isinstance(measure, list) or not measure or not all(isinstance(m, str) for m in measure):
        raise ValueError(f"measure must be a non-empty list of names from: {', '.join(MEASUREMENTS)}")
    unknown = [m for m in measure if m not in MEASUREMENTS]
    if unknown:
        raise ValueError(f"unknown measurement '{unknown[0]}'; choose from: {', '.join(MEASUREMENTS)}")
    flags = {}
    for key in ("video", "trajectory"):
        flags[key] = data.get(key, False)
        if not isinstance(flags[key], bool):
            raise ValueError(f"{key} must be true or false, got {flags[key]!r}")
    horizon = data.get("horizon", HORIZON)
    if isinstance(horizon, bool) or not isinstance(horizon, (int, float)) or not 0 <= horizon < math.inf:
        raise ValueError(f"horizon must be a finite number of seconds >= 0, got {horizon!r}")
    return Record(measure=tuple(dict.fromkeys(measure)), horizon=float(horizon), **flags)


def expand(grid: dict) -> list:
    """The jobs of a [grid] table: the Cartesian product of its parameters, times the union of
    the products of its [[grid.cases]] (if any). Settings dicts in grid order, duplicates
    (the same id twice) dropped."""
    shared = {key: value for key, value in grid.items() if key != "cases"}
    cases = grid.get("cases", [{}])
    if not isinstance(cases, list) or not all(isinstance(case, dict) for case in cases):
        raise ValueError("cases must be tables: [[grid.cases]]")
    if not cases:
        raise ValueError("cases is an empty list: the grid would have no jobs")
    shared_values = _checked(shared, "[grid]")
    jobs, seen = {}, {}     # seen: scene path -> is it one world (each scene file loads once)
    for number, case in enumerate(cases, 1):
        where = f"[[grid.cases]] number {number}"
        both = sorted(set(case) & set(shared))
        if both:
            raise ValueError(f"parameter '{both[0]}' is in both [grid] and {where}; give it in one place")
        lists = {**shared_values, **_checked(case, where)}
        _check_product(lists, where if grid.get("cases") else "[grid]", seen)
        _require_few("jobs in the grid", len(jobs) + math.prod(len(values) for values in lists.values()))
        keys = sorted(lists)
        for combination in itertools.product(*(lists[key] for key in keys)):
            settings = dict(zip(keys, combination))
            jobs.setdefault(job_id(settings), settings)
    return list(jobs.values())


def _checked(table: dict, where: str) -> dict:
    lists = {}
    for key, raw in table.items():
        if key not in PARAMETERS:
            raise ValueError(f"unknown parameter '{key}' in {where}; parameters: {', '.join(PARAMETERS)}")
        lists[key] = _values(key, raw)
    return lists


def _check_product(lists: dict, where: str, seen: dict) -> None:
    """One product of parameter lists runs: exactly one kind of source, every parameter one that
    source takes, every scene loadable as one world."""
    sources = [key for key in SOURCES if key in lists]
    if len(sources) != 1:
        raise ValueError(f"{where} needs exactly one of scene = [...] or workload = [...]"
                         + ("; put scenes and workloads in separate [[grid.cases]]" if sources else ""))
    given = [key for key in WORKLOAD_PARAMETERS if key in lists]
    if sources[0] == "scene":
        if given:
            raise ValueError(f"parameter '{given[0]}' applies to workloads only (a scene file builds its own world)")
        for scene in lists["scene"]:
            _check_scene(scene, seen)
        return
    for workload in lists["workload"]:
        for key in given:
            if not takes(workload, key):
                raise ValueError(f"workload '{workload}' takes no parameter '{key}'")


def _check_scene(name: str, seen: dict) -> None:
    """The scene loads and is one world (a scene of panels compares its own settings)."""
    from ...model.scenefile import load_scene, resolve_scene_path
    key = resolve_scene_path(name).resolve()
    if key not in seen:
        seen[key] = load_scene(name).world is not None
    if not seen[key]:
        raise ValueError(f"scene '{name}' is made of panels or chapters; a sweep job needs a scene of one world")


def check_plot(plot, jobs: list, record: Record) -> dict:
    """The [plot] table, checked against the sweep's parameters and measurements."""
    if not isinstance(plot, dict):
        raise ValueError("plot must be a table: [plot]")
    unknown = [key for key in plot if key not in PLOT_KEYS]
    if unknown:
        raise ValueError(f"unknown key '{unknown[0]}' in [plot]; it takes: {', '.join(PLOT_KEYS)}")
    kind = plot.get("kind")
    if kind not in ("pareto", "curve"):
        raise ValueError(f"[plot] kind must be \"pareto\" or \"curve\", got {kind!r}")
    ys = plot.get("y")
    ys = [ys] if isinstance(ys, str) else ys
    if not isinstance(ys, list) or not ys or not all(isinstance(y, str) for y in ys):
        raise ValueError("[plot] y must be a measurement or a list of them")
    missing = [y for y in ys if y not in record.measure or y == "warnings"]
    if missing:
        raise ValueError(f"[plot] y '{missing[0]}' is not a numeric measurement of this sweep "
                         f"(measure = {list(record.measure)})")
    swept = {key for job in jobs for key in job}
    x = plot.get("x", "cost" if kind == "pareto" else None)
    if kind == "pareto" and (x != "cost" or "cost" not in record.measure):
        raise ValueError("a pareto plot has cost on x: put \"cost\" in measure (and leave x out)")
    if kind == "pareto" and "method" not in swept:
        raise ValueError("a pareto plot draws one marker per method: give method = [...] in the grid")
    if kind == "curve" and (x not in NUMERIC or x not in swept):
        numeric = ", ".join(k for k in NUMERIC if k in swept) or "none here"
        raise ValueError(f"[plot] x must be a numeric parameter of the grid ({numeric}), got {x!r}")
    by = plot.get("by")
    if by is not None and (by not in swept or by == x):
        raise ValueError(f"[plot] by must be another parameter of the grid, got {by!r}")
    scales = {}
    for key in ("xscale", "yscale"):
        scales[key] = plot.get(key, "log" if kind == "pareto" else "linear")
        if scales[key] not in ("linear", "log"):
            raise ValueError(f"[plot] {key} must be \"linear\" or \"log\", got {scales[key]!r}")
    title = plot.get("title", "")
    if not isinstance(title, str):
        raise ValueError("[plot] title must be a string")
    return dict(kind=kind, x=x, y=tuple(ys), by=by, title=title, **scales)
