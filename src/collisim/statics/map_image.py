"""Bitmaps in and out of collision maps: an image read into a solid mask (dark is solid), and
exact shapes drawn into an image (rasterize_polygons) for scenes and benchmarks.

A pixel's centre is (ox + (j + 0.5) * cell, oy + (i + 0.5) * cell), row i counted from the bottom:
the mask is flipped from the image's top-down rows, and rasterize_polygons draws top-down rows
so that its output goes straight into CollisionMap.from_image.
"""
from __future__ import annotations

import numbers
import os
from pathlib import Path

import cv2
import numpy as np

from ..core.checks import number
from ..core.compiling import compiled, kernel

_CHANNELS = {"r": 0, "g": 1, "b": 2, "a": 3}   # of an RGB(A) image


def solid_mask(image, threshold: float, channel) -> np.ndarray:
    """(ny, nx) bool, row 0 = the lowest y: the pixels of image (a path or an array, see
    CollisionMap.from_image) darker than threshold."""
    return np.flipud(_solid_pixels(*_read_image(image), threshold, channel)).copy()


def world_origin(value) -> np.ndarray:
    """origin as (2,) float64 world (x, y), or ValueError with one line."""
    try:
        origin = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        origin = None
    if origin is None or origin.shape != (2,):
        raise ValueError(f"origin must be two numbers (x, y), got {value!r:.40}")
    if not np.all(np.isfinite(origin)):
        raise ValueError(f"origin must be finite, got {origin.tolist()}")
    return origin


def _read_image(image) -> tuple:
    """(pixels (h, w, c), white): c = 1 (gray), 3 (RGB) or 4 (RGBA), in the image's own dtype
    (uint8, uint16 or float), and the value of full brightness (255, 65535 or 1.0)."""
    if isinstance(image, (str, os.PathLike)):
        image = _read_file(Path(image))
    elif not isinstance(image, np.ndarray):
        raise ValueError(f"map image must be a path or a numpy array, got {type(image).__name__}")
    if not (image.ndim == 2 or (image.ndim == 3 and image.shape[2] in (1, 3, 4))):
        raise ValueError(f"map image must be (height, width) gray or (height, width, 3 or 4) RGB(A), "
                         f"got shape {image.shape}")
    if image.size == 0:
        raise ValueError(f"map image is empty (shape {image.shape})")
    image = image.reshape(*image.shape[:2], -1)
    if image.dtype in (np.uint8, np.uint16):
        return image, float(np.iinfo(image.dtype).max)
    if image.dtype.kind != "f":
        raise ValueError(f"map image must be uint8, uint16 or float in [0, 1] (dark is solid), got {image.dtype}")
    if not (np.all(np.isfinite(image)) and image.min() >= 0.0 and image.max() <= 1.0):
        raise ValueError("a float map image must hold values in [0, 1] (0 black, 1 white)")
    return image, 1.0


def _read_file(path: Path) -> np.ndarray:
    """A file read by OpenCV, its channels reordered from BGR(A) to RGB(A)."""
    if not path.exists():
        raise ValueError(f"cannot read map image {path}: not found")
    if not path.is_file():
        raise ValueError(f"cannot read map image {path}: not a file")
    try:
        image = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    except cv2.error:
        image = None
    if image is None:
        raise ValueError(f"cannot read map image {path}: not an image file OpenCV can read")
    if image.ndim == 3 and image.shape[2] >= 3:
        image = image[:, :, [2, 1, 0, 3][:image.shape[2]]]
    return image


def _channel_index(channel, channels: int) -> int:
    """The index of `channel` (an index or "r", "g", "b", "a") in an image of `channels` channels."""
    if isinstance(channel, str) and channel.lower() in _CHANNELS and channels > 1:
        index = _CHANNELS[channel.lower()]
    elif isinstance(channel, numbers.Integral) and not isinstance(channel, bool):
        index = int(channel)
    else:
        index = -1
    if not 0 <= index < channels:
        if channels == 1:
            raise ValueError(f"unknown channel {channel!r} for a gray map image; use None or 0")
        names = ", ".join(repr(name) for name in "rgba"[:channels])
        raise ValueError(f"unknown channel {channel!r} for an {'RGBA'[:channels]} map image; "
                         f"use None, 0..{channels - 1} or one of {names}")
    return index


def _solid_pixels(pixels: np.ndarray, white: float, threshold: float, channel) -> np.ndarray:
    """(h, w) bool, image rows (row 0 at the top): pixels whose brightness (0..1, the mean of the
    colour channels or the chosen channel; `white` is full brightness) is below threshold."""
    channels = pixels.shape[2]
    index = None if channel is None else _channel_index(channel, channels)
    tested = pixels[:, :, :3] if index is None else pixels[:, :, index:index + 1]
    solid = tested.mean(axis=2, dtype=np.float64) / white < threshold
    if channels == 4 and index != 3:
        solid &= pixels[:, :, 3] > 0   # fully transparent pixels are free
    return solid


def rasterize_polygons(polygons, size, cell=1.0, origin=(0.0, 0.0), circles=()) -> np.ndarray:
    """A bitmap of exact shapes, for from_image with the same cell and origin.

    polygons: a list of (p, 2) world-space vertex lists (p >= 3; each closed, filled by the
    even-odd rule); circles: (cx, cy, r) rows; size: (height, width) pixels. Returns
    (height, width) uint8, image rows (row 0 at the top): 0 where solid, 255 where free. A pixel
    is solid iff its centre (ox + (j + 0.5) * cell, oy + (i + 0.5) * cell), i counted from the
    bottom, lies inside a polygon or within distance r of a circle's centre.
    """
    try:
        height, width = (int(n) for n in size)
    except (TypeError, ValueError):
        raise ValueError(f"size must be (height, width), got {size!r:.40}") from None
    if height < 1 or width < 1 or (height, width) != tuple(size):
        raise ValueError(f"size must be two positive whole numbers (height, width), got {size!r:.40}")
    cell = number("cell", cell, positive=True)
    x0, y0 = world_origin(origin)
    solid = np.zeros((height, width), np.bool_)
    for k, polygon in enumerate(polygons):
        vertices = _shape_rows(f"polygon {k}", polygon, 2)
        if len(vertices) < 3:
            raise ValueError(f"polygon {k} must have at least 3 vertices, got {len(vertices)}")
        _fill_polygon(vertices, x0, y0, cell, solid)
    circles = _shape_rows("circles", circles, 3)
    if np.any(circles[:, 2] < 0.0):
        raise ValueError("circles must have radius r >= 0 (rows cx, cy, r)")
    _fill_circles(circles, x0, y0, cell, solid)
    return np.where(solid[::-1], 0, 255).astype(np.uint8)


def _shape_rows(name: str, value, columns: int) -> np.ndarray:
    """A finite (k, columns) float64 array, or ValueError naming `name`."""
    try:
        rows = np.array(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be numbers, got {value!r:.40}") from None
    rows = rows.reshape(0, columns) if rows.size == 0 else rows
    if rows.ndim != 2 or rows.shape[1] != columns:
        raise ValueError(f"{name} must have shape (k, {columns}), got shape {rows.shape}")
    if not np.all(np.isfinite(rows)):
        raise ValueError(f"{name} contains NaN or inf")
    return rows


@kernel
def _first_centre_at_or_above(value, origin, cell, n):
    """The first index k in 0..n whose pixel centre origin + (k + 0.5) * cell is >= value (found
    from the estimate, then stepped, so it agrees with the centre formula exactly)."""
    k = int(min(max(np.ceil((value - origin) / cell - 0.5), 0.0), float(n)))
    while k > 0 and origin + (k - 0.5) * cell >= value:
        k -= 1
    while k < n and origin + (k + 0.5) * cell < value:
        k += 1
    return k


@compiled
def _fill_polygon(vertices, x0, y0, cell, solid):
    """Mark the pixels of solid (rows from the bottom) whose centres are inside the polygon
    vertices (p, 2): per row of centres, the edges' crossings, sorted; a centre is inside when an
    odd number of crossings lies left of it (edges count half-open in y, so a vertex on the row
    is crossed once)."""
    ny, nx = solid.shape
    p = vertices.shape[0]
    low, high = vertices[:, 1].min(), vertices[:, 1].max()
    crossings = np.empty(p)
    for i in range(_first_centre_at_or_above(low, y0, cell, ny), ny):
        y = y0 + (i + 0.5) * cell
        if y > high:
            break
        count = 0
        for k in range(p):
            ax, ay = vertices[k, 0], vertices[k, 1]
            bx, by = vertices[(k + 1) % p, 0], vertices[(k + 1) % p, 1]
            if (ay > y) != (by > y):
                crossings[count] = ax + (y - ay) * (bx - ax) / (by - ay)
                count += 1
        xs = np.sort(crossings[:count])
        for pair in range(0, count - 1, 2):
            # centres strictly right of the odd crossing, up to the even one
            for j in range(_first_centre_at_or_above(xs[pair], x0, cell, nx), nx):
                x = x0 + (j + 0.5) * cell
                if x > xs[pair + 1]:
                    break
                if x > xs[pair]:
                    solid[i, j] = True


@kernel
def _fill_circles(circles, x0, y0, cell, solid):
    """Mark the pixels of solid (rows from the bottom) whose centres lie within a circle
    (rows cx, cy, r): (x - cx)^2 + (y - cy)^2 <= r^2."""
    ny, nx = solid.shape
    for c in range(circles.shape[0]):
        cx, cy, r = circles[c, 0], circles[c, 1], circles[c, 2]
        for i in range(_first_centre_at_or_above(cy - r, y0, cell, ny), ny):
            dy = y0 + (i + 0.5) * cell - cy
            if dy > r:
                break
            for j in range(_first_centre_at_or_above(cx - r, x0, cell, nx), nx):
                dx = x0 + (j + 0.5) * cell - cx
                if dx > r:
                    break
                if dx * dx + dy * dy <= r * r:
                    solid[i, j] = True
