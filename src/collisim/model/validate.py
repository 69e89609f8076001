"""Checks that turn a state the engine cannot run into one clear line (ValueError).

Arrays are checked for shape before anything is broadcast (a single body written flat as
[x, y] is a mistake, not two bodies), numbers for type and range, and the initial state for
overlaps: bodies that start inside each other, or inside a segment, have no defined contact
normal or order of events, so every method would silently do something different.
Touching is allowed (within a relative 1e-9, so bodies placed touching by arithmetic pass).
"""
from __future__ import annotations

import numbers
from pathlib import Path

import numpy as np

TOUCH_TOLERANCE = 1e-9   # relative to the contact distance


def number(name: str, value, *, low=None, high=None, positive=False) -> float:
    """value as a finite float, or ValueError naming `name`."""
    if isinstance(value, bool) or not isinstance(value, (numbers.Real, np.number)):
        raise ValueError(f"{name} must be a number, got {value!r}")
    value = float(value)
    if positive and not (np.isfinite(value) and value > 0):
        raise ValueError(f"{name} must be a finite number > 0, got {value:g}")
    if not np.isfinite(value):
        raise ValueError(f"{name} must be finite, got {value:g}")
    if (low is not None and value < low) or (high is not None and value > high):
        if high is None:
            raise ValueError(f"{name} must be >= {low:g}, got {value:g}")
        if low is None:
            raise ValueError(f"{name} must be <= {high:g}, got {value:g}")
        raise ValueError(f"{name} must be in [{low:g}, {high:g}], got {value:g}")
    return value


def is_whole(value, minimum: int = 0) -> bool:
    """Is value a whole number (an int or numpy integer, not a bool) >= minimum?"""
    return isinstance(value, (int, np.integer)) and not isinstance(value, bool) and value >= minimum


def whole_pair(name: str, value) -> tuple:
    """(a, b), both whole numbers >= 1, or ValueError naming `name`."""
    try:
        a, b = value
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be two whole numbers, got {value!r}") from None
    if not (is_whole(a, 1) and is_whole(b, 1)):
        raise ValueError(f"{name} must be two whole numbers >= 1, got {value!r}")
    return int(a), int(b)


def per_body(name: str, value, n: int, columns: int | None = None) -> np.ndarray:
    """A per-body array: (n,) or (n, columns) float64, from a scalar (or one row) broadcast to
    every body, or from an array of exactly that shape. Anything else is one clear line."""
    array = _floats(name, value)
    shape = (n,) if columns is None else (n, columns)
    single = () if columns is None else (columns,)
    if array.shape not in (shape, single, ()):
        want = f"({n},)" if columns is None else f"({n}, {columns})"
        raise ValueError(f"{name} must have shape {want} for {n} bod{'y' if n == 1 else 'ies'}, "
                         f"got shape {array.shape}")
    _check_finite(name, array)
    return np.broadcast_to(array, shape).copy()


def vector(name: str, value, example: str) -> np.ndarray:
    """A 2D vector (2,) float64, finite; a scalar is refused rather than copied into both
    components (gravity=-9.81 would otherwise pull diagonally)."""
    array = _floats(name, value)
    if array.shape != (2,):
        raise ValueError(f"{name} must be a vector of two numbers, such as {example}, got {_short(value)}")
    _check_finite(name, array)
    return array


def is_file(path) -> bool:
    """Is path a regular file? False, not OSError, for a path the system cannot even look up
    (a name over 255 characters raised "File name too long" through the command line)."""
    try:
        return Path(path).is_file()
    except OSError:
        return False


def missing_file(what: str, text: str) -> str:
    """The line for a path that is not a readable file: not found, a folder, or something else."""
    path = Path(text)
    try:
        if path.is_dir():
            return f"{what} {text} is a folder, not a file"
        if path.exists():
            return f"{what} {text} is not a regular file"
    except OSError as error:
        return f"{what} {text} cannot be looked up: {error.strerror}"
    return f"{what} not found: {text}"


def positions_array(value) -> np.ndarray:
    """Centres (n, 2); [] for no bodies. One body is [[x, y]], never [x, y]."""
    return _rows("positions", value, 2, "(n, 2)", hint=" (one body is written [[x, y]])")


def segments_array(value) -> np.ndarray:
    """Segments (m, 4) rows x0, y0, x1, y1; None or [] for none; one row may be written flat."""
    return _rows("segments", [] if value is None else value, 4, "(m, 4) rows x0, y0, x1, y1", flat_row=True)


def collision_map(value):
    """A CollisionMap (statics/collision_map.py) or None."""
    from ..statics.collision_map import CollisionMap
    if value is not None and not isinstance(value, CollisionMap):
        raise ValueError(f"map must be a collisim.CollisionMap or None, got {type(value).__name__}")
    return value


def _rows(name: str, value, columns: int, shape_text: str, hint: str = "", flat_row: bool = False) -> np.ndarray:
    """A finite (k, columns) float64 array, or ValueError naming `name`."""
    array = _floats(name, value)
    if array.size == 0:
        return np.zeros((0, columns))
    if flat_row and array.shape == (columns,):
        array = array[None]
    if array.ndim != 2 or array.shape[1] != columns:
        extra = hint if array.shape == (columns,) else ""
        raise ValueError(f"{name} must have shape {shape_text}, got shape {array.shape}{extra}")
    _check_finite(name, array)
    return array


def no_overlaps(world) -> None:
    """ValueError naming the first pair of bodies, or body and segment, that overlap."""
    from ..narrowphase.registry import contacts
    from ..narrowphase.statics import touching_segments
    if world.n >= 2:
        found = contacts(world)
        pairs, depths = found["pairs"], found["depths"]
        deep = np.flatnonzero(depths > world.radii[pairs].sum(axis=1) * TOUCH_TOLERANCE)
        if deep.size:
            i, j = pairs[deep[0]]
            raise ValueError(f"bodies {i} and {j} overlap by {depths[deep[0]]:.3g} at the start; "
                             f"place them apart or touching")
    if len(world.segments):
        pairs, depths = touching_segments(world.positions, world.radii, world.segments, world.box)
        depths = _polygon_depths(world, pairs, depths)
        deep = np.flatnonzero(depths > world.radii[pairs[:, 0]] * TOUCH_TOLERANCE)
        if deep.size:
            i, s = pairs[deep[0]]
            raise ValueError(f"body {i} overlaps segment {s} by {depths[deep[0]]:.3g} at the start; "
                             f"place it apart or touching")
    if world.map is not None:
        _outside_map(world)


def _polygon_depths(world, pairs, depths):
    """depths of (body, segment) pairs found by bounding circles, exact for polygon bodies."""
    from ..model.kinds import CIRCLE
    from ..narrowphase.manifold import polygon_segment_manifold
    polygons = np.flatnonzero(world.shapes[pairs[:, 0]] != CIRCLE)
    if polygons.size == 0:
        return depths
    depths, vertices = depths.copy(), world.placed_vertices()
    for row in polygons:   # a start-up check, once per world: not a hot path
        m = polygon_segment_manifold(vertices, world.vertex_start, pairs[row, 0], world.segments, pairs[row, 1], 0.0)
        depths[row] = m[3] if m[2] > 0 else -1.0
    return depths


def _outside_map(world) -> None:
    """ValueError naming the first body that starts inside the collision map's solid, or
    overlapping its contour chains (which ccd collides with exactly)."""
    from ..narrowphase.statics import touching_segments
    depths = world.radii - world.map.distance(world.positions)
    # the distance field is exact only to about a cell: its own tolerance is half a cell
    deep = np.flatnonzero(depths > 0.5 * world.map.cell + world.radii * TOUCH_TOLERANCE)
    if deep.size:
        i = deep[0]
        raise ValueError(f"body {i} at ({world.positions[i, 0]:g}, {world.positions[i, 1]:g}) starts inside the "
                         f"collision map's solid; place it in free space")
    pairs, depths = touching_segments(world.positions, world.radii, world.map.segments, world.box)
    deep = np.flatnonzero(depths > world.radii[pairs[:, 0]] * TOUCH_TOLERANCE)
    if deep.size:
        i = pairs[deep[0], 0]
        raise ValueError(f"body {i} overlaps the collision map's outline by {depths[deep[0]]:.3g} at the start; "
                         f"place it in free space")


def _floats(name: str, value) -> np.ndarray:
    """value as a float64 array, or ValueError naming `name` (None too: numpy makes it NaN)."""
    if value is None:
        raise ValueError(f"{name} must be numbers, got None")
    try:
        return np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be numbers, got {_short(value)}") from None


def _check_finite(name: str, array: np.ndarray) -> None:
    if not np.all(np.isfinite(array)):
        raise ValueError(f"{name} contains NaN or inf")


def _short(value) -> str:
    text = repr(value)
    return text if len(text) <= 40 else text[:37] + "..."
