"""Draws scenes/pinball.png, the level of the collision_map scene: run `python scenes/_pinball_level.py`.

A bitmap, as a level designer would paint one: black is solid, white is free. 640 x 360
pixels for a 32 x 18 world, so a pixel is 0.05 world units. Kept as a script so the picture
can be changed and redrawn; the scene reads only the PNG.
"""
from pathlib import Path

import cv2
import numpy as np

WIDTH, HEIGHT, CELL = 640, 360, 0.05
SOLID, FREE = 0, 255


def px(x, y):
    """World (x, y) -> integer pixel (column, row); rows go down."""
    return int(round(x / CELL)), int(round((HEIGHT * CELL - y) / CELL))


def thick_line(image, a, b, width):
    cv2.line(image, px(*a), px(*b), SOLID, max(1, int(round(width / CELL))), cv2.LINE_8)


def draw_level() -> np.ndarray:
    image = np.full((HEIGHT, WIDTH), FREE, np.uint8)
    cv2.rectangle(image, (0, 0), (WIDTH - 1, HEIGHT - 1), SOLID, 8)          # the table's rim
    thick_line(image, (0.0, 15.0), (12.6, 11.2), 0.4)                        # the funnel
    thick_line(image, (32.0, 15.0), (19.4, 11.2), 0.4)
    for row, y in enumerate((9.0, 7.4, 5.8)):                                # pegs, staggered
        for k in range(12):
            x = 2.6 + 2.5 * k + (1.25 if row % 2 else 0.0)
            if x < 31.0:
                cv2.circle(image, px(x, y), int(round(0.42 / CELL)), SOLID, -1, cv2.LINE_8)
    for x in np.arange(4.0, 32.0, 4.0):                                      # bins at the bottom
        thick_line(image, (x, 0.0), (x, 2.6), 0.3)
    for side in (-1, 1):                                                     # two slanted bumpers
        cx = 16.0 + side * 10.5
        tri = np.array([px(cx - 1.6, 3.8), px(cx + 1.6, 3.8), px(cx, 4.9)], np.int32)
        cv2.fillPoly(image, [tri], SOLID, cv2.LINE_8)
    return image


if __name__ == "__main__":
    path = Path(__file__).with_name("pinball.png")
    cv2.imwrite(str(path), draw_level())
    print(f"wrote {path}")
