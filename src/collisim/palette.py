"""Colours that read well on a dark background (RGB, uint8)."""
import numpy as np

BACKGROUND = (18, 20, 28)
BOX = (200, 204, 214)
TEXT = (230, 232, 238)
DIM_TEXT = (140, 146, 160)
HIGHLIGHT = (255, 214, 102)
FLASH = (255, 255, 255)

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
