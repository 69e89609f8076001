"""Typeset text for the explainer layer: mathtext's coverage of a text at a size in pixels,
kept on disk from run to run (textcache.py), pasted in a colour, shrunk to a width, or cut into
two lines for a label that does not fit on one."""
from __future__ import annotations

from functools import lru_cache

import cv2
import numpy as np

from . import raster, textcache


def text_pixels(pixels: float) -> float:
    """The size text asked to be `pixels` tall is typeset at (text_image's half-pixel steps)."""
    return max(4.0, round(pixels * 2.0) / 2.0)


@lru_cache(maxsize=512)
def text_image(text: str, pixels: float) -> np.ndarray:
    """The coverage (h, w) float32 in [0, 1] of `text` typeset by mathtext at about `pixels`
    tall, cached: a caption is typeset once, not every frame, and kept on disk for the runs
    after (textcache.py)."""
    size = text_pixels(pixels)   # half-pixel steps keep the cache small
    kept = textcache.path(text, size)   # (named once: a digest of matplotlib's settings)
    ink = textcache.load(kept)
    if ink is None:
        ink = typeset(text, size)
        textcache.save(kept, ink)
    return ink.astype(np.float32) / 255.0


def typeset(text: str, size: float) -> np.ndarray:
    """The coverage (h, w) uint8 of text typeset by mathtext at size points (72 dpi).

    mathtext's own rasterizer gives the coverage directly, with all of the ink. Drawing the text
    on a matplotlib Figure and decoding its PNG, as before, imported matplotlib's figure
    machinery (0.2-0.3 s of a first frame) and cut off glyphs that stand out of their advance
    (a T's left arm; a last letter, which took a trailing space to keep)."""
    from matplotlib.font_manager import FontProperties
    from matplotlib.mathtext import MathTextParser
    try:
        image = MathTextParser("agg").parse(text, dpi=72, prop=FontProperties(size=size)).image
    except ValueError as error:   # matplotlib's message spans lines: its last one says what is wrong
        lines = [line.strip() for line in str(error).splitlines() if line.strip()]
        why = (lines[-1] if lines else str(error)).removeprefix("ParseException: ")
        raise ValueError(f"text {text!r} is not valid mathtext (an odd number of $ signs, or an unknown "
                         f"command): {why}") from None
    return np.array(image, np.uint8)


def fit_width(image: np.ndarray, width: float) -> np.ndarray:
    """Shrink text that would not fit its strip (a long caption in a narrow panel)."""
    if image.shape[1] <= width or width < 8:
        return image
    scale = width / image.shape[1]
    size = (max(1, int(width)), max(1, round(image.shape[0] * scale)))   # (a short line: the nearest pixel)
    return cv2.resize(image, size, interpolation=cv2.INTER_AREA)


def paste(canvas, coverage: np.ndarray, left: int, top: int, color_rgb, alpha: float) -> tuple:
    """Paint `color_rgb` through `coverage` (h, w) at (left, top), clipped to the canvas.
    Returns the rectangle (x, y, w, h) of the text, unclipped (for the tests' bounds check)."""
    h, w = coverage.shape
    x0, y0 = max(left, 0), max(top, 0)
    x1, y1 = min(left + w, canvas.shape[1]), min(top + h, canvas.shape[0])
    if x1 > x0 and y1 > y0:
        weight = alpha * coverage[y0 - top:y1 - top, x0 - left:x1 - left, None]
        region = canvas[y0:y1, x0:x1].astype(np.float32)
        color = np.array(raster.bgr(color_rgb), np.float32)
        canvas[y0:y1, x0:x1] = (region + weight * (color - region) + 0.5).astype(np.uint8)
    return (left, top, w, h)


def split_line(text: str):
    """The text cut in two at the space nearest its middle outside math ($...$), a cut after
    punctuation preferred; None if it has no such space."""
    cuts, inside = [], False
    for k, char in enumerate(text):
        inside ^= char == "$"
        if char == " " and not inside and 0 < k < len(text) - 1:
            cuts.append((abs(k - len(text) / 2) - (len(text) / 4 if text[k - 1] in ",:;" else 0), k))
    if not cuts:
        return None
    cut = min(cuts)[1]
    return text[:cut], text[cut + 1:]


def two_lines(first: str, second: str, pixels: float) -> np.ndarray:
    """The coverage of two typeset lines, left-aligned, one under the other."""
    top, bottom = text_image(first, pixels), text_image(second, pixels)
    gap = int(round(0.2 * pixels))
    out = np.zeros((top.shape[0] + gap + bottom.shape[0], max(top.shape[1], bottom.shape[1])), np.float32)
    out[:top.shape[0], :top.shape[1]] = top
    out[top.shape[0] + gap:, :bottom.shape[1]] = bottom
    return out
