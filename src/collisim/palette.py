"""Colours (RGB, uint8) and the themes that choose them.

The player draws in the colours of the active theme: `BACKGROUND`, `BOX`, `TEXT`, `DIM_TEXT`,
`HIGHLIGHT` and `FLASH` below are the active theme's, read at draw time (so scene overlays
that use `palette.TEXT` follow the theme too). `using(theme)` makes a theme active for the
length of a render. Body colours (PARTICLES) read well on both themes.
"""
from __future__ import annotations

import sys
from contextlib import contextmanager
from dataclasses import dataclass, replace

import numpy as np


@dataclass(frozen=True)
class Theme:
    """The colours of everything but the bodies (RGB)."""
    background: tuple
    box: tuple
    text: tuple
    dim_text: tuple
    highlight: tuple
    flash: tuple

    def with_background(self, rgb) -> "Theme":
        return replace(self, background=tuple(int(c) for c in rgb))


THEMES = {
    "dark": Theme(background=(18, 20, 28), box=(200, 204, 214), text=(230, 232, 238), dim_text=(140, 146, 160),
                  highlight=(255, 214, 102), flash=(255, 255, 255)),
    "light": Theme(background=(246, 244, 238), box=(70, 74, 88), text=(28, 30, 38), dim_text=(104, 110, 124),
                   highlight=(196, 112, 0), flash=(40, 40, 48)),
}

BACKGROUND, BOX, TEXT, DIM_TEXT, HIGHLIGHT, FLASH = (
    THEMES["dark"].background, THEMES["dark"].box, THEMES["dark"].text, THEMES["dark"].dim_text,
    THEMES["dark"].highlight, THEMES["dark"].flash)


def _activate(theme: Theme) -> None:
    module = sys.modules[__name__]
    for name in ("background", "box", "text", "dim_text", "highlight", "flash"):
        setattr(module, name.upper(), getattr(theme, name))


def active() -> Theme:
    return Theme(BACKGROUND, BOX, TEXT, DIM_TEXT, HIGHLIGHT, FLASH)


@contextmanager
def using(theme: Theme):
    """Make `theme` the active one while drawing; the previous one comes back after."""
    previous = active()
    _activate(theme)
    try:
        yield theme
    finally:
        _activate(previous)


# Distinct, saturated but soft hues; the first three are the 250-particle scene's three sizes.
PARTICLES = np.array([
    (94, 172, 255),    # blue
    (255, 122, 138),   # pink
    (120, 220, 160),   # green
    (255, 176, 84),    # orange
    (196, 140, 255),   # violet
    (255, 226, 110),   # yellow
    (96, 214, 224),    # cyan
    (240, 100, 100),   # red
], dtype=np.uint8)


def default_colors(radii: np.ndarray) -> np.ndarray:
    """One colour per distinct radius (smallest first), cycling through the palette.

    radii: (n,) -> colors: (n, 3) uint8
    """
    _, size_class = np.unique(np.round(radii, 9), return_inverse=True)
    return PARTICLES[size_class % len(PARTICLES)]


def pick(index: int) -> tuple:
    return tuple(int(c) for c in PARTICLES[index % len(PARTICLES)])
