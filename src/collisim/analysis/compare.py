"""`collisim compare`: run one scene under several methods and measure each against the others.

Methods are labels: "discrete xK" (collisim's discrete steps, K substeps per frame), "ccd"
(collisim's exact event-driven method) and "pymunk xK" (the same World in pymunk, see
collisim.analysis.reference.pymunk_mirror). The default set is discrete x1, discrete x8, ccd, pymunk x1.

A scene made of panels (such as `tunneling`) is compared panel by panel: every panel's world
runs under every method, and each row's label starts with the panel's title ("title: ccd"); the
panels' own method and substeps are ignored, since the point is to run all methods on them.

Each row (a dict of plain numbers, ready for JSON):
    panel, method, label, seconds (simulated), cost (wall seconds per simulated second, after a
    warm-up run so compilation is not counted), energy_drift, momentum_drift (None when walls,
    segments or accelerations act on the particles: then momentum is not conserved and the
    number would mean nothing), max_overlap (radii), outside_end / outside_ever (particles whose
    centre left the box), missed_pairs / missed_segments (pass-throughs, see collisim.analysis.metrics),
    collisions / pair_collisions / wall_collisions / segment_collisions (as each method counts
    them), wall_pressure, position_error (RMS distance from the ccd run at `horizon` seconds, in
    radii; None if ccd cannot run the world), horizon, warnings, and error (None, or why the
    method could not run: that row's measurements are then None).

A world with polygons (scenes/polygons.py) runs under discrete and pymunk; ccd refuses it, and
its row says so ("ccd: could not run (...)"), with position_error None for every row. max_overlap
is the narrow phase's deepest contact there, over the smaller body's radius (a polygon's bounding
circle's); missed_pairs measures circles (centre paths against radii), so it is None ("n/a") for
such a world; energy counts rotation (World.inertias), which both engines record.

Where pymunk and collisim differ, and which one is right
-------------------------------------------------------
Measured on particles_250 and on 12 seeds of the same gas (10 s each), single_bounce,
two_bodies and segment/pair tunnelling lanes (tests/test_vs_pymunk.py):

* Isolated pair contacts, restitution (pairs and walls), segment and pair tunnelling: the same.
  With the same positions (both step p += v·dt without gravity) pymunk's contact solve gives
  collisim's two-body response to round-off, and the same lanes tunnel, lane by lane.
* Kinetic energy of the gas: conserved by all three (drift ~1e-14); pymunk's position
  correction moves positions only, and isolated contacts are exact in its solver.
* Bouncing under gravity (single_bounce): pymunk is the one that is off. Its semi-implicit Euler
  lags half a step per fall and its bounce targets the pre-gravity velocity, so each flight
  lasts about one step longer than the exact 2·v/g: the n-th bounce comes ~1.1·n steps late,
  and the energy swings by 2.4 % between bounces (0.23 % at 8 substeps: first order in dt).
  collisim's ccd matches the closed form; collisim's discrete bounces are at most one step late
  and do not accumulate, because its wall response reflects the overshoot and keeps the energy.
* two_bodies: the first two collisions agree; at 60 fps both discrete engines (collisim and
  pymunk) add a third one at ~8 s that ccd does not have. Each discrete engine takes the contact
  normal after up to a step of overlap; that O(dt) error in the first collision grows to whole
  units by 5 s. At 64 substeps both follow ccd (0.02 units at 5 s): ccd is right.
* Collision rate and wall pressure of the gas: at 60 fps both discrete engines count fewer pair
  collisions than ccd (pymunk -3.4 %, collisim discrete -1.7 %, averaged over 12 seeds, with a
  run-to-run scatter of 2 %), and both converge to ccd's rate at 8 substeps. A discrete engine
  meets a pair late and then puts it back at contact distance (collisim at once, pymunk through
  its bias velocity), so on the way out the pair is closer than it should be by v·τ (τ < dt the
  lateness): an effectively smaller collision diameter, which lowers the collision rate and the
  excess pressure. ccd is right; both discrete engines are first order in dt, as expected.
* Overlaps in the frames: pymunk lets contacts overlap for a step and removes them on the next,
  up to 1.1 radii of the smaller circle in particles_250 at 60 fps. collisim's discrete method
  separates each pair at once, and separates the step's contacts once more after the walls
  (a wall bounce can push a particle back into its partner), yet its frames still show overlaps
  of up to 0.28 radii: sequential pair resolution in a cluster of three pushes one into a
  neighbour already resolved. That is repaired at the next step. ccd never overlaps.
* Grazing contacts: a discrete step sees a pair only if it overlaps at a step end, so a grazing
  contact whose overlap lasts less than a step is missed: 0.6-0.7 % of the pair collisions of
  particles_250 at 60 fps, in both collisim discrete and pymunk; none in ccd (missed_pairs).
"""
from __future__ import annotations

import json
import math
import re
import time
import warnings

import numpy as np

from . import metrics
from ..engine import simulate
from ..core.kinds import CIRCLE

DEFAULT_METHODS = ("discrete x1", "discrete x8", "ccd", "pymunk x1")
_LABEL = re.compile(r"^(discrete|pymunk)(?:\s*x\s*(\d+))?$|^(ccd)$")


def parse_method(label: str) -> tuple:
    """'discrete x8' -> ('discrete', 8); 'ccd' -> ('ccd', 1); 'pymunk' -> ('pymunk', 1)."""
    text = " ".join(str(label).lower().split())
    match = _LABEL.match(text)
    if not match:
        raise ValueError(f"unknown method '{label}'; use e.g. {', '.join(DEFAULT_METHODS)}")
    if match.group(3):
        return "ccd", 1
    substeps = int(match.group(2) or 1)
    if substeps < 1:
        raise ValueError(f"method '{label}': substeps must be >= 1")
    return match.group(1), substeps


def method_label(engine: str, substeps: int) -> str:
    return "ccd" if engine == "ccd" else f"{engine} x{substeps}"


def compare(scene, methods=None, seconds=None, horizon: float = 0.25, keep_trajectories: bool = False) -> list:
    """Run `scene` under each method and measure it: one row (dict) per method (and panel).

    methods: labels such as "discrete x8" (a list, or one comma-separated string); default
    DEFAULT_METHODS. seconds: simulated duration (default: the scene's). horizon: when to
    compare positions with the ccd run. keep_trajectories: each row also holds its run as
    row["trajectory"] (for render_comparison). Bad input raises ValueError with one line.
    """
    if isinstance(methods, str):
        methods = [m for m in methods.split(",") if m.strip()]
    methods = [parse_method(m) for m in (DEFAULT_METHODS if methods is None else methods)]
    if not methods:
        raise ValueError("no methods to compare")
    if not (isinstance(horizon, (int, float)) and math.isfinite(horizon) and horizon >= 0):
        raise ValueError(f"horizon must be a finite number of seconds >= 0, got {horizon}")
    if seconds is not None:
        scene = scene.with_options(seconds=seconds)
    worlds = distinct_worlds(scene)
    rows = []
    for title, single in worlds:
        rows.extend(_compare_world(title, single, methods, horizon, keep_trajectories))
    return rows


def render_comparison(rows: list, path, size=None):
    """Render the runs kept by compare(..., keep_trajectories=True) side by side, each titled
    by its label: the comparison a person can watch. Returns the path."""
    from ..model.scene import RenderSettings
    from ..pipeline import render
    panels = [(row["label"], row["trajectory"]) for row in rows if row.get("trajectory") is not None]
    if not panels:
        raise ValueError("no run to render: every method failed on this scene")
    return render(panels, path, size, settings=RenderSettings(trails=20))


def distinct_worlds(scene) -> list:
    """(title, single-world scene) for each distinct world of a scene. A scene of panels or
    chapters may show one world under several methods; compare runs each world once under all
    methods, titled by what it holds ("4 particles, 1 segment")."""
    if scene.world is not None:
        return [("", scene)]
    found = {}
    for part in scene.panels or scene.chapters:
        for _, single in distinct_worlds(getattr(part, "scene", part)):
            w = single.world
            key = b"".join(a.tobytes() for a in (w.positions, w.velocities, w.radii, w.masses, w.segments, w.box))
            found.setdefault(key, single)
    return [(_describe_world(single.world), single) for single in found.values()]


def _describe_world(world) -> str:
    text = f"{world.n} particle{'s' * (world.n != 1)}"
    if len(world.segments):
        text += f", {len(world.segments)} segment{'s' * (len(world.segments) != 1)}"
    return text


def _compare_world(title: str, scene, methods: list, horizon: float, keep: bool) -> list:
    runs = {(engine, k): _timed_run(scene, engine, k) for engine, k in dict.fromkeys(methods)}
    reference = runs.get(("ccd", 1)) or _timed_run(scene, "ccd", 1, timed=False)
    rows = []
    for engine, substeps in methods:
        label = method_label(engine, substeps)
        row = {"panel": title, "method": label, "label": f"{title}: {label}" if title else label,
               "seconds": float(scene.frames / scene.fps), "horizon": float(horizon)}
        row.update(_measure(scene.world, runs[(engine, substeps)], reference[0], horizon))
        if keep:
            row["trajectory"] = runs[(engine, substeps)][0]
        rows.append(row)
    return rows


def run_method(scene, engine: str, substeps: int):
    """Simulate a single-world scene with one method (as parse_method names it): the Trajectory.

    Only the simulation: no warm-up, no timing, no measurement (the caller decides those)."""
    if engine == "pymunk":
        from .reference import simulate_pymunk
        return simulate_pymunk(scene, substeps=substeps)
    return simulate(scene.replace(method=engine, substeps=substeps))


def _timed_run(scene, engine: str, substeps: int, timed: bool = True) -> tuple:
    """(trajectory or None, wall seconds per simulated second or None, error text or None)."""
    try:
        with warnings.catch_warnings(record=True):
            warnings.simplefilter("always")
            if timed:   # compile (or load the compiled kernels) outside the timing
                run_method(scene.replace(seconds=min(scene.seconds, 2.0 / scene.fps)), engine, substeps)
            start = time.perf_counter()
            traj = run_method(scene, engine, substeps)
            cost = (time.perf_counter() - start) / (scene.frames / scene.fps)
    except Exception as error:   # an engine that cannot run this world is a finding, not a crash
        return None, None, one_line(error)
    return traj, cost, None


def one_line(error: BaseException) -> str:
    """An error as one line of a table: a ValueError is collisim's own refusal, in its words;
    anything else is a finding, named by its type."""
    text = (str(error) if isinstance(error, ValueError) else f"{type(error).__name__}: {error}").strip()
    return text.splitlines()[0] if text else type(error).__name__


_MEASURES = ("cost", "energy_drift", "momentum_drift", "max_overlap", "outside_end", "outside_ever",
             "missed_pairs", "missed_segments", "collisions", "pair_collisions", "wall_collisions",
             "segment_collisions", "wall_pressure", "position_error")


def _measure(world, run: tuple, reference, horizon: float) -> dict:
    traj, cost, error = run
    row = dict.fromkeys(_MEASURES)
    row.update(warnings=[], error=error)
    if traj is None:
        return row
    row.update(measure(world, traj, reference, horizon, cost))
    return row


def measure(world, traj, reference, horizon: float, cost=None) -> dict:
    """compare's measurements of one trajectory of `world` (the _MEASURES keys and warnings):
    `reference` is the ccd trajectory for position_error (None leaves it None), `horizon` when
    to compare positions, `cost` is passed through as the row's wall seconds per simulated second."""
    outside_end, outside_ever = metrics.outside(traj, world)
    circles = bool(np.all(world.shapes == CIRCLE))   # pass-throughs measure circles
    pushed = traj.wall_collisions.sum() + traj.segment_collisions.sum() > 0 or np.any(world.accelerations != 0)
    return dict(
        cost=cost,
        energy_drift=metrics.energy_drift(traj, world),
        momentum_drift=None if pushed else metrics.momentum_drift(traj),
        max_overlap=metrics.max_overlap(traj),
        outside_end=outside_end, outside_ever=outside_ever,
        missed_pairs=int(metrics.missed_collisions(traj).sum()) if circles else None,
        missed_segments=int(metrics.missed_segment_crossings(traj, world).sum()),
        collisions=int(traj.collisions.sum()), pair_collisions=int(traj.pair_collisions.sum()),
        wall_collisions=int(traj.wall_collisions.sum()), segment_collisions=int(traj.segment_collisions.sum()),
        wall_pressure=metrics.wall_pressure(traj, world),
        position_error=None if reference is None else metrics.position_error(traj, reference, horizon),
        warnings=[str(w) for w in traj.warnings])


# --- output ------------------------------------------------------------------------------------

_COLUMNS = (  # header, unit, how to show a row
    ("method", "", lambda r: r["label"]),
    ("wall time", "s/sim s", lambda r: _number(r["cost"], "{:.3g}")),
    ("energy drift", "rel", lambda r: _number(r["energy_drift"], "{:.1e}")),
    ("momentum drift", "rel", lambda r: _number(r["momentum_drift"], "{:.1e}", none="n/a")),
    ("max overlap", "radii", lambda r: _number(r["max_overlap"], "{:.3g}", none=_missing(r))),
    ("outside", "end/ever", lambda r: _pair(r["outside_end"], r["outside_ever"])),
    ("missed", "pairs/segment", lambda r: _pair(r["missed_pairs"], r["missed_segments"], none=_missing(r))),
    ("collisions", "pair+wall+seg", lambda r: _number(r["collisions"], "{:d}")),
    ("wall pressure", "F/L", lambda r: _number(r["wall_pressure"], "{:.4g}")),
    ("vs ccd", "radii", lambda r: _number(r["position_error"], "{:.2g}")),
)


def _number(value, pattern: str, none: str = "-") -> str:
    return none if value is None else pattern.format(value)


def _pair(a, b, none: str = "-") -> str:
    if a is None and b is None:
        return "-"
    return f"{none if a is None else a}/{none if b is None else b}"


def _missing(row) -> str:
    """How a measurement the row lacks shows: "-" if the method could not run, else "n/a"."""
    return "-" if row.get("error") else "n/a"


def format_table(rows: list) -> str:
    """An aligned text table, one line per row, units under the headers; errors listed below."""
    if not rows:
        return "(no rows)"
    horizon = rows[0]["horizon"]
    headers = [name if name != "vs ccd" else f"vs ccd @{horizon:g}s" for name, _, _ in _COLUMNS]
    units = [f"[{unit}]" if unit else "" for _, unit, _ in _COLUMNS]
    cells = [[show(row) for _, _, show in _COLUMNS] for row in rows]
    widths = [max(len(text) for text in column) for column in zip(headers, units, *cells)]

    def line(texts):
        first = texts[0].ljust(widths[0])
        return "  ".join([first] + [t.rjust(w) for t, w in zip(texts[1:], widths[1:])]).rstrip()
    lines = [line(headers), line(units)] + [line(c) for c in cells]
    for row in rows:
        if row.get("error"):
            lines.append(f"{row['label']}: could not run ({row['error']})")
        for note in row.get("warnings") or []:
            lines.append(f"{row['label']}: note: {note}")
    return "\n".join(lines)


def rows_to_json(rows: list) -> str:
    """The rows as a JSON array (numbers as numbers, None as null, inf as a string)."""
    return json.dumps([{key: _plain(value) for key, value in row.items() if key != "trajectory"} for row in rows],
                      indent=2)


def _plain(value):
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, (np.integer,)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        value = float(value)
        return value if math.isfinite(value) else str(value)
    return value
