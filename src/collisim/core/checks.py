"""Checks that turn a value collisim cannot use into one clear line (ValueError).

Arrays are checked for shape before anything is broadcast (a single body written flat as
[x, y] is a mistake, not two bodies), numbers for type and range, paths for being files. The
initial state's overlaps are checked where the engine starts (engine/start.py).
"""
from __future__ import annotations

import numbers
from pathlib import Path

import numpy as np

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


class StaticMap:
    """What a World accepts as its map: statics/collision_map.CollisionMap derives from it, so
    the model checks a map, and loads one saved with a trajectory (kinds, by class name),
    without importing the statics that build one."""
    kinds = {}

    def __init_subclass__(cls, **options):
        super().__init_subclass__(**options)
        StaticMap.kinds[cls.__name__] = cls


def collision_map(value):
    """A CollisionMap (statics/collision_map.py) or None."""
    if value is not None and not isinstance(value, StaticMap):
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
