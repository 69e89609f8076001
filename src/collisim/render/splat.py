"""Compiled anti-aliased discs and rings, drawn straight into a BGR frame.

A disc is its centre in float pixel coordinates (OpenCV's convention: pixel (i, j) is the unit
square centred on (i, j)), its radius in pixels and its colour. Each pixel the disc reaches is
blended towards the colour by c, the fraction of the pixel's square the disc covers:
value + (colour - value) * c, rounded. Only the pixels of each disc's bounding box are
visited; discs are drawn in order (later over earlier), clipped to the canvas or to a clip
rectangle, all in one compiled call, or from BAND_DISCS discs on one call per band of rows, each
on a thread of its own, with the same bytes (render/bands.py).

How c is computed, and how far it is from the exact area: coverage.py.

Rings (the annulus between r - t/2 and r + t/2, what cv2.circle draws with thickness t) are the
outer disc's fractions minus the inner disc's, each as above, so an annulus covers
pi ((r + t/2)^2 - (r - t/2)^2) within the sum of the two discs' bounds.

The kernels take an (h, w, 3) canvas: a uint8 frame (the blend rounds: bias = 0.5) or a float
one (bias 0), which is how the tests read the fractions themselves (`disc_coverage`).
"""
from __future__ import annotations

import math

import numpy as np

from ..core.compiling import compiled
from .bands import RING_DISCS, in_bands
from .coverage import (SCRATCH, SMALL, TINY, _edge, _fraction, _mixed, _normalized, _normalizer, _row, _shifted,
                       _small_cover, _tent_weight)


@compiled(inline="always", error_model="numpy")
def _clip(x, lo, hi):
    return int(min(max(x, lo), hi))


@compiled(inline="always", error_model="numpy")
def _runs(t0, t1, o0, o1, left, right):
    """Clip a row's touched columns [t0, t1] to the columns [left, right) and split them around
    the run [o0, o1] (empty: o0 = o1 + 1): returns a, before, run0, run1, after, b with
    [a, before] and [after, b] the columns left and right of the run, [run0, run1] the run's."""
    lo, hi = float(left), float(right)
    a = _clip(t0, lo, hi)
    b = _clip(t1, lo - 1.0, hi - 1.0)
    before = min(_clip(o0 - 1.0, lo - 1.0, hi), b)
    run0 = max(_clip(o0, lo - 1.0, hi), a)
    run1 = min(_clip(o1, lo - 1.0, hi), b)
    after = max(_clip(o1 + 1.0, lo - 1.0, hi), a)
    return a, before, run0, run1, after, b


@compiled(inline="always", error_model="numpy")
def _color(colors, n):
    """Colour n as three numbers, loaded once a disc: read from the array at every pixel, it was
    loaded again after every store into the canvas (which the compiler cannot prove apart from
    it), and a tiny disc took twice as long."""
    return colors[n, 0], colors[n, 1], colors[n, 2]


@compiled(inline="always", error_model="numpy")
def _blend(canvas, j, i, color, c, bias):
    v = canvas[j, i, 0]
    canvas[j, i, 0] = v + (color[0] - v) * c + bias
    v = canvas[j, i, 1]
    canvas[j, i, 1] = v + (color[1] - v) * c + bias
    v = canvas[j, i, 2]
    canvas[j, i, 2] = v + (color[2] - v) * c + bias


@compiled(inline="always", error_model="numpy")
def _fill(canvas, j, i0, i1, color, bias):
    b, g, r = color[0] + bias, color[1] + bias, color[2] + bias
    for i in range(i0, i1 + 1):
        canvas[j, i, 0] = b
        canvas[j, i, 1] = g
        canvas[j, i, 2] = r


@compiled(inline="always", error_model="numpy")
def _tent(canvas, clip, cx, cy, area, color, bias):
    """A sub-pixel disc: its area spread bilinearly over the four pixels around (cx, cy)."""
    left, top, right, bottom = clip
    i0 = int(math.floor(cx))
    j0 = int(math.floor(cy))
    wx1 = cx - i0
    wy1 = cy - j0
    for dj in range(2):
        j = j0 + dj
        if j < top or j >= bottom:
            continue
        wy = area * (wy1 if dj else 1.0 - wy1)
        for di in range(2):
            i = i0 + di
            if i < left or i >= right:
                continue
            c = wy * (wx1 if di else 1.0 - wx1)
            if c > 0.0:
                _blend(canvas, j, i, color, min(c, 1.0), bias)


@compiled(inline="always", error_model="numpy")
def _small_disc(canvas, clip, cx, cy, r, color, bias, scratch):
    left, top, right, bottom = clip
    i0, j0, w, h, alpha, beta = _small_cover(cx, cy, r, scratch)
    for jj in range(max(top - j0, 0), min(h, bottom - j0)):
        for ii in range(max(left - i0, 0), min(w, right - i0)):
            c = _mixed(_normalized(scratch[jj, ii], alpha, beta), i0 + ii - cx, j0 + jj - cy, r)
            if c > 0.0:
                _blend(canvas, j0 + jj, i0 + ii, color, min(c, 1.0), bias)


@compiled(error_model="numpy")
def _large_disc(canvas, clip, cx, cy, r, color, bias):
    """A disc of radius >= SMALL, row by row: the inside run filled, the boundary blended."""
    left, top, right, bottom = clip
    rs = _shifted(r)
    j0 = _clip(math.floor(cy - r - 0.5) + 1.0, float(top), bottom - 1.0)
    j1 = _clip(math.ceil(cy + r + 0.5) - 1.0, float(top), bottom - 1.0)
    for j in range(j0, j1 + 1):
        dy = j - cy
        t0, t1, o0, o1 = _row(cx, dy, r)
        a, before, run0, run1, after, b = _runs(t0, t1, o0, o1, left, right)
        for i in range(a, before + 1):
            c = _edge(i - cx, dy, r, rs)
            if c > 0.0:
                _blend(canvas, j, i, color, c, bias)
        _fill(canvas, j, run0, run1, color, bias)
        for i in range(after, b + 1):
            c = _edge(i - cx, dy, r, rs)
            if c > 0.0:
                _blend(canvas, j, i, color, c, bias)


@compiled(error_model="numpy")
def _covered_disc(canvas, clip, cx, cy, r, color, bias, scratch):
    """A disc of radius >= TINY, blended by covered fractions.

    The loops over discs choose between this and _tent themselves: with the choice behind one
    more function (inlined or not), a sub-pixel disc, the common case of a large gas, took 60
    ns instead of 26 (numba's reference counting of the arrays around that call)."""
    if r < SMALL:
        _small_disc(canvas, clip, cx, cy, r, color, bias, scratch)
    else:
        _large_disc(canvas, clip, cx, cy, r, color, bias)


@compiled(inline="always", error_model="numpy")
def _off_clip(cx, cy, r, clip):
    """Whether a disc cannot reach the clip rectangle (or cannot be drawn at all)."""
    left, top, right, bottom = clip
    return not (math.isfinite(cx) and math.isfinite(cy) and math.isfinite(r)) or (
        cx + r + 1.0 < left or cy + r + 1.0 < top or cx - r - 1.0 > right or cy - r - 1.0 > bottom)


@compiled(error_model="numpy")
def _small_ring(canvas, clip, cx, cy, outer, inner, color, bias, scratch, inner_scratch):
    """A ring of outer radius in [TINY, SMALL): each disc's fractions computed once into its own
    scratch (as _small_disc does), the inner's subtracted from the outer's. The same numbers as
    _fraction's, at half the cost of computing both discs again at every pixel."""
    left, top, right, bottom = clip
    i0, j0, w, h, alpha, beta = _small_cover(cx, cy, outer, scratch)
    k0, l0, wi, hi, alpha_in, beta_in = 0, 0, 0, 0, 1.0, 0.0
    if inner >= TINY:
        k0, l0, wi, hi, alpha_in, beta_in = _small_cover(cx, cy, inner, inner_scratch)
    for jj in range(max(top - j0, 0), min(h, bottom - j0)):
        for ii in range(max(left - i0, 0), min(w, right - i0)):
            dx, dy = i0 + ii - cx, j0 + jj - cy
            c = _mixed(_normalized(scratch[jj, ii], alpha, beta), dx, dy, outer)
            if inner < TINY:
                c -= _tent_weight(dx, dy, inner)
            else:
                u, v = i0 + ii - k0, j0 + jj - l0      # the pixel in the inner disc's box
                inside = _normalized(inner_scratch[v, u], alpha_in, beta_in) if 0 <= u < wi and 0 <= v < hi else 0.0
                c -= _mixed(inside, dx, dy, inner)
            if c > 0.0:
                _blend(canvas, j0 + jj, i0 + ii, color, min(c, 1.0), bias)


@compiled(error_model="numpy")
def _large_ring(canvas, clip, cx, cy, outer, inner, color, bias, scratch):
    """A ring of outer radius >= SMALL, row by row, skipping the columns inside the inner disc."""
    left, top, right, bottom = clip
    rs_out, rs_in = _shifted(outer), _shifted(inner)
    alpha_in, beta_in = _normalizer(cx, cy, inner, scratch)
    j0 = _clip(math.floor(cy - outer - 0.5) + 1.0, float(top), bottom - 1.0)
    j1 = _clip(math.ceil(cy + outer + 0.5) - 1.0, float(top), bottom - 1.0)
    for j in range(j0, j1 + 1):
        dy = j - cy
        t0, t1, _, _ = _row(cx, dy, outer)
        _, _, v0, v1 = _row(cx, dy, inner)
        if inner < TINY:
            v0, v1 = 1.0, 0.0                # no pixel lies inside a sub-pixel disc
        # the columns inside the inner disc stay untouched: visit [a, before] and [after, b]
        a, before, _, _, after, b = _runs(t0, t1, v0, v1, left, right)
        for part in range(2):
            first, last = (a, before) if part == 0 else (after, b)
            for i in range(first, last + 1):
                dx = i - cx
                c = (_fraction(dx, dy, outer, rs_out, 1.0, 0.0)
                     - _fraction(dx, dy, inner, rs_in, alpha_in, beta_in))
                if c > 0.0:
                    _blend(canvas, j, i, color, min(c, 1.0), bias)


@compiled(error_model="numpy")
def _ring(canvas, clip, cx, cy, outer, inner, color, bias, scratch, inner_scratch):
    if outer < TINY:     # both sub-pixel: one splat of the annulus's area
        _tent(canvas, clip, cx, cy, math.pi * (outer * outer - inner * inner), color, bias)
    elif outer < SMALL:
        _small_ring(canvas, clip, cx, cy, outer, inner, color, bias, scratch, inner_scratch)
    else:
        _large_ring(canvas, clip, cx, cy, outer, inner, color, bias, scratch)


@compiled(nogil=True, error_model="numpy")
def splat_rings(canvas, clip, centres, radii, thickness, colors, bias):
    """Draw rings and discs into canvas (h, w, 3), in order, touching only the pixels of clip:
    (left, top, right, bottom), columns [left, right) and rows [top, bottom), within the canvas.
    Each is the annulus between radii - thickness/2 and radii + thickness/2 (each (n,) pixels;
    an inner radius <= 0 makes a disc, and so does a negative thickness: the disc of radius
    radii, cv2's FILLED). centres (n, 2) float pixels, colors (n, 3) in the canvas's channel
    order, bias 0.5 for integer canvases (rounding), 0.0 for float ones. Shapes with a
    non-finite centre or radius, or an outer radius <= 0, are skipped. Discs and rings are one
    kernel: a first render compiles one, not two."""
    if clip[2] <= clip[0] or clip[3] <= clip[1]:
        return
    scratch = np.empty((SCRATCH, SCRATCH))
    inner_scratch = np.empty((SCRATCH, SCRATCH))
    for n in range(centres.shape[0]):
        cx, cy = centres[n, 0], centres[n, 1]
        half = 0.5 * thickness[n]
        outer, inner = (radii[n], 0.0) if half < 0.0 else (radii[n] + half, radii[n] - half)
        if not (outer > 0.0) or not math.isfinite(inner) or _off_clip(cx, cy, outer, clip):
            continue
        if inner <= 0.0 and outer < TINY:
            _tent(canvas, clip, cx, cy, math.pi * outer * outer, _color(colors, n), bias)
        elif inner <= 0.0:
            _covered_disc(canvas, clip, cx, cy, outer, _color(colors, n), bias, scratch)
        else:
            _ring(canvas, clip, cx, cy, outer, inner, _color(colors, n), bias, scratch, inner_scratch)


# --- the Python side -------------------------------------------------------------------------------

def _bias(canvas) -> float:
    return 0.5 if np.issubdtype(canvas.dtype, np.integer) else 0.0


def _prepare(canvas, centres, radii, colors):
    """Contiguous float64 arrays for the kernels: centres (n, 2), radii (n,), colors (n, k)."""
    if canvas.ndim != 3:
        raise ValueError(f"canvas must be (h, w, channels), got shape {canvas.shape}")
    centres = np.ascontiguousarray(np.asarray(centres, np.float64).reshape(-1, 2))
    n = len(centres)
    radii = np.ascontiguousarray(np.broadcast_to(np.asarray(radii, np.float64), (n,)))
    colors = np.asarray(colors, np.float64)
    colors = np.ascontiguousarray(np.broadcast_to(colors, (n, colors.shape[-1])))
    if canvas.shape[2] != 3 or colors.shape[1] != 3:
        raise ValueError(f"discs are drawn in 3 channels: got a canvas of {canvas.shape[2]} and colours of "
                         f"{colors.shape[1]}")
    return _read_only(centres), _read_only(radii), _read_only(colors)


def _read_only(array):
    """A read-only view: numba types read-only and writable arrays apart, so inputs that are
    sometimes one (a broadcast view) and sometimes the other (a copy) compiled each kernel twice."""
    view = array.view()
    view.flags.writeable = False
    return view


def clip_rect(canvas, clip=None) -> tuple:
    """The pixels drawing may touch, (left, top, right, bottom): columns [left, right) and rows
    [top, bottom), the canvas's intersection with `clip` (the whole canvas if None)."""
    height, width = canvas.shape[0], canvas.shape[1]
    if clip is None:
        return 0, 0, width, height
    left, top, right, bottom = (int(v) for v in clip)
    return max(left, 0), max(top, 0), max(min(right, width), 0), max(min(bottom, height), 0)


def draw_discs(canvas, centres_px, radii_px, colors, clip=None) -> None:
    """Filled anti-aliased discs into canvas (h, w, 3) in place, in order (in bands of rows on
    threads from BAND_DISCS discs on: render/bands.py).
    centres_px (n, 2), radii_px (n,) or one radius, colors (n, 3) or one (3,) colour in the
    canvas's channel order (BGR for a frame). clip: (left, top, right, bottom), the only pixels
    drawn (clip_rect); discs keep their shapes, cut at its edges."""
    centres, radii, colors = _prepare(canvas, centres_px, radii_px, colors)
    if len(centres):
        filled = _read_only(np.full(len(centres), -1.0))
        in_bands(splat_rings, canvas, clip_rect(canvas, clip), len(centres), centres, radii, filled, colors,
                 _bias(canvas))


def draw_annuli(canvas, centres_px, radii_px, thickness_px, colors, clip=None) -> None:
    """Anti-aliased rings into canvas in place: annuli of width thickness_px (n,) or one,
    centred on radii_px, as cv2.circle draws outlines; a negative thickness fills the disc of
    radius radii_px (cv2's FILLED). Other arguments as for draw_discs."""
    centres, radii, colors = _prepare(canvas, centres_px, radii_px, colors)
    thickness = _read_only(np.ascontiguousarray(np.broadcast_to(np.asarray(thickness_px, np.float64), radii.shape)))
    if len(centres):
        work = RING_DISCS * len(centres)
        in_bands(splat_rings, canvas, clip_rect(canvas, clip), work, centres, radii, thickness, colors, _bias(canvas))


def disc_coverage(shape, centres_px, radii_px) -> np.ndarray:
    """The covered fractions (h, w) float64 of discs drawn alone on an empty canvas of `shape`
    (h, w): what draw_discs blends each pixel by (where the discs do not overlap)."""
    canvas = np.zeros((shape[0], shape[1], 3))
    draw_discs(canvas, centres_px, radii_px, [1.0, 1.0, 1.0])
    return canvas[:, :, 0]


def ring_coverage(shape, centres_px, radii_px, thickness_px) -> np.ndarray:
    """As disc_coverage, for rings."""
    canvas = np.zeros((shape[0], shape[1], 3))
    draw_annuli(canvas, centres_px, radii_px, thickness_px, [1.0, 1.0, 1.0])
    return canvas[:, :, 0]

