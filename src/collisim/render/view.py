"""World to pixels: fit the box into a rectangle of the canvas with a margin, y flipped.

Pixel centres sit at integer coordinates (OpenCV's convention), so a world point maps to the
pixel whose centre is nearest it.
"""
from __future__ import annotations

import numpy as np


class View:
    """Maps world points into the pixel rectangle `rect` = (left, top, width, height)."""

    def __init__(self, box, rect, margin: float = 0.04):
        self.box = np.asarray(box, dtype=np.float64)
        left, top, width, height = rect
        xmin, ymin, xmax, ymax = self.box
        pad = margin * min(width, height)
        self.scale = min((width - 2 * pad) / (xmax - xmin), (height - 2 * pad) / (ymax - ymin))
        # centre the box in the rectangle
        self.origin_x = left + 0.5 * (width - self.scale * (xmax - xmin)) - self.scale * xmin
        self.origin_y = top + 0.5 * (height - self.scale * (ymax - ymin)) + self.scale * ymax
        self.rect = rect

    def to_pixels(self, points) -> np.ndarray:
        """points: (..., 2) world -> (..., 2) float pixel coordinates (x right, y down)."""
        points = np.asarray(points, dtype=np.float64)
        out = np.empty_like(points)
        # in place, without temporaries (a player maps every body at every frame)
        x, y = out[..., 0], out[..., 1]
        np.multiply(points[..., 0], self.scale, out=x)
        x += self.origin_x
        np.multiply(points[..., 1], -self.scale, out=y)     # origin_y - scale·y, to the last bit
        y += self.origin_y
        return out

    def length(self, world_length):
        return np.asarray(world_length) * self.scale
