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


def parse_color(value, what: str = "colour") -> tuple:
    """(r, g, b) ints from '#RRGGBB' (or 'RRGGBB') or three values in 0..255; ValueError naming
    `what` otherwise."""
    if isinstance(value, str):
        text = value.strip().lstrip("#")
        if len(text) == 6 and all(c in "0123456789abcdefABCDEF" for c in text):
            return tuple(int(text[k:k + 2], 16) for k in (0, 2, 4))
        raise ValueError(f"{what} must look like #1a2b3c, got '{value}'")
    try:
        rgb = tuple(value)
    except TypeError:
        raise ValueError(f"{what} must be '#RRGGBB' or three values in 0..255, got {value!r}") from None
    if len(rgb) != 3 or not all(isinstance(c, (int, np.integer)) and not isinstance(c, bool) and 0 <= c <= 255
                                for c in rgb):
        raise ValueError(f"{what} must be '#RRGGBB' or three whole values in 0..255, got {value!r}")
    return tuple(int(c) for c in rgb)


def parse_colors(values, what: str = "colors") -> np.ndarray:
    """(n, 3) uint8 RGB from a list of colours, each as parse_color takes it."""
    if isinstance(values, str) or not hasattr(values, "__len__"):
        raise ValueError(f"{what} must be a list of colours, one per body ('#RRGGBB' or (r, g, b)), got {values!r}")
    return np.array([parse_color(v, f"{what}[{k}]") for k, v in enumerate(values)], np.uint8).reshape(-1, 3)


def luminance(rgb) -> float:
    """Relative luminance (WCAG 2, sRGB) of an RGB colour, 0 for black to 1 for white."""
    channels = np.asarray(rgb, float) / 255.0
    linear = np.where(channels <= 0.04045, channels / 12.92, ((channels + 0.055) / 1.055) ** 2.4)
    return float(linear @ (0.2126, 0.7152, 0.0722))


def contrast(a, b) -> float:
    """WCAG 2 contrast ratio of two colours, 1 (the same) to 21 (black on white)."""
    high, low = sorted((luminance(a), luminance(b)), reverse=True)
    return (high + 0.05) / (low + 0.05)


def theme_for(background) -> str:
    """The theme whose text and HUD read best on `background`: the one whose dimmest text
    (the HUD's) has the higher contrast with it."""
    return max(THEMES, key=lambda name: contrast(THEMES[name].dim_text, background))


def default_colors(radii: np.ndarray) -> np.ndarray:
    """One colour per distinct radius (smallest first), cycling through the palette.

    radii: (n,) -> colors: (n, 3) uint8
    """
    _, size_class = np.unique(np.round(radii, 9), return_inverse=True)
    return PARTICLES[size_class % len(PARTICLES)]


def pick(index: int) -> tuple:
    return tuple(int(c) for c in PARTICLES[index % len(PARTICLES)])
