"""Charts of a sweep table, as its [plot] table asks (matplotlib's Agg canvas: no display needed).

kind = "pareto": one panel per y (an error), cost on x, log-log, one colour and marker per
    method, substeps beside each point and the Pareto front as steps: the panels of
    `collisim bench accuracy`, drawn by its own plot_error.
kind = "curve": one panel per y against the swept parameter x, one line per method (and
    substep count), each point the mean over the jobs that share it (other parameters, such
    as phases or seeds, are averaged: over phases a 0/1 miss becomes a tunnelling fraction).
by = "<parameter>": one figure per value of that parameter, <table>_<value>.png; otherwise
    <table>.png, beside the table. Rows with an error or without the numbers are left out.
"""
from __future__ import annotations

import math
import re
from pathlib import Path

from ...core.files import save_figure
from ..bench.accuracy import ErrorKind, plot_error
from ..compare import method_label

COUNTS = ("outside_end", "outside_ever", "missed_pairs", "missed_segments", "collisions", "pair_collisions",
          "wall_collisions", "segment_collisions", "events")
LABELS = {
    "cost": "wall seconds per simulated second", "energy_drift": "relative energy drift",
    "momentum_drift": "relative momentum drift", "max_overlap": "largest overlap [radii]",
    "outside_end": "particles outside at the end", "outside_ever": "particles outside the box (ever)",
    "missed_pairs": "missed pair collisions", "missed_segments": "missed segment hits",
    "collisions": "collisions", "pair_collisions": "pair collisions", "wall_collisions": "wall collisions",
    "segment_collisions": "segment collisions", "wall_pressure": "wall pressure",
    "position_error": "position error vs ccd [RMS radii]", "events": "impacts logged",
}


def number(text):
    """A table cell as a float, or None if empty or not a number."""
    try:
        return float(text)
    except (TypeError, ValueError):
        return None


def plot_sweep(rows: list, plot: dict, table: Path, name: str = "") -> list:
    """Draw the charts for the rows of a sweep table (dicts of strings); returns the PNG paths."""
    rows = [row for row in rows if not row.get("error")]
    groups = {}
    for row in rows:
        groups.setdefault(row.get(plot["by"], "") if plot["by"] else "", []).append(row)
    if not groups:
        raise ValueError(f"nothing to plot: {table} has no row without an error")
    paths = []
    for value, mine in sorted(groups.items()):
        suffix = f"_{re.sub(r'[^A-Za-z0-9_.-]+', '-', value)}" if plot["by"] else ""
        path = Path(table).with_name(f"{Path(table).stem}{suffix}.png")
        title = plot["title"] or f"{name or Path(table).stem}: {plot['kind']}"
        if plot["by"]:
            title += f", {plot['by']} = {value}"
        _figure(mine, plot, path, title)
        paths.append(path)
    return paths


def _figure(rows: list, plot: dict, path: Path, title: str) -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    count = len(plot["y"])
    columns = min(count, 3)
    lines = math.ceil(count / columns)
    figure = Figure(figsize=(5 * columns + 1, 4 * lines + 0.6), dpi=110)
    FigureCanvasAgg(figure)
    panels = figure.subplots(lines, columns, squeeze=False).ravel()
    for axes, y in zip(panels, plot["y"]):
        (_pareto_panel if plot["kind"] == "pareto" else _curve_panel)(axes, rows, plot, y)
    for axes in panels[count:]:
        axes.set_visible(False)
    panels[0].legend(loc="best", fontsize=8)
    figure.suptitle(title)
    figure.tight_layout()
    save_figure(figure, path)


def _pareto_panel(axes, rows: list, plot: dict, y: str) -> None:
    """Error y against cost with the Pareto front: bench accuracy's panel (plot_error)."""
    points = []
    for row in rows:
        cost, error = number(row.get("cost")), number(row.get(y))
        if cost is not None and cost > 0 and error is not None and not math.isnan(error):
            points.append({"cost": cost, y: error, "engine": row.get("method", ""),
                           "substeps": int(number(row.get("substeps")) or 1)})
    floor = 0.1 if y in COUNTS else 1e-17     # zeros cannot sit on a log axis (as bench accuracy)
    plot_error(axes, points, ErrorKind(y, LABELS.get(y, y), floor))
    axes.set_xlabel(LABELS["cost"])


def _curve_panel(axes, rows: list, plot: dict, y: str) -> None:
    """Mean of y against x, one line per method (and substep count)."""
    x = plot["x"]
    lines = {}
    for row in rows:
        at, value = number(row.get(x)), number(row.get(y))
        if at is None or value is None or math.isnan(value):
            continue
        method = row.get("method") or "run"
        label = method_label(method, int(number(row.get("substeps")) or 1)) if row.get("substeps") else method
        lines.setdefault(label, {}).setdefault(at, []).append(value)
    for label, points in sorted(lines.items()):
        xs = sorted(points)
        axes.plot(xs, [sum(points[v]) / len(points[v]) for v in xs], marker="o", markersize=3, label=label)
    axes.set_xscale(plot["xscale"])
    axes.set_yscale(plot["yscale"])
    axes.set_xlabel(x)
    axes.set_ylabel(f"{LABELS.get(y, y)}\n(mean over the other parameters)", fontsize=9)
    axes.grid(True, which="both", alpha=0.3)
