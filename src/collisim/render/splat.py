"""Compiled anti-aliased discs and rings, drawn straight into a BGR frame.

A disc is its centre in float pixel coordinates (OpenCV's convention: pixel (i, j) is the unit
square centred on (i, j)), its radius in pixels and its colour. Each pixel the disc reaches is
blended towards the colour by c, the fraction of the pixel's square the disc covers:
value + (colour - value) * c, rounded. Only the pixels of each disc's bounding box are
visited; discs are drawn in order (later over earlier), clipped to the canvas, all in one
compiled call.

How c is computed, and how far it is from the exact area
--------------------------------------------------------
Exact areas need an arcsine per pixel corner on the boundary (about 40 ns each on the project's
machine), and a disc 1-2 px wide has 9-25 such corners, against a budget of 100 ns a disc for
250 000 discs in 25 ms. So:

* Exact where it is cheap: a pixel entirely inside the disc (its farthest corner within r) gets
  exactly the colour; a pixel the disc does not reach (its nearest point at r or beyond) is
  not touched.
* Boundary pixels (`_edge`): near the pixel the circle is replaced by its tangent at the point
  nearest the pixel's centre, and c is the exact area of the unit square on the inner side of
  that line, which is exact for a straight edge at any angle (unlike clamp(r - d + 0.5, 0, 1),
  exact only for axis-aligned edges and off by up to 0.043 at 45 degrees). The arc bends
  inwards from its tangent; over a whole disc that would add pi/12 px^2 (pi times 1/12, the
  variance of the square's projection on any direction), whatever r, so the line is put at
  r' = sqrt(r^2 - 1/12) instead of r, which makes the expected area exact.
* Discs with 0.5 <= r < SMALL (4 px): their boundary fractions are then mapped affinely (towards
  0 if they sum too high, towards 1 if too low, so none leaves [0, 1]) to make the disc's
  fractions sum to pi r^2 exactly, computed on the whole disc whether clipped or not.
* Discs with r < TINY (0.5 px, smaller than a pixel): box-filtered area would keep such a dot in
  one pixel until it crossed a pixel border, so slow motion would jump (by up to 0.3 px at
  r = 0.3). Its area pi r^2 is instead spread bilinearly over the four pixels around its centre
  (exactly the coverage of a unit square of density pi r^2): the total is exactly pi r^2 and
  the centroid exactly the centre, so sub-pixel motion is smooth. From TINY to BLEND (area 1,
  r = 0.564) the two are mixed linearly in r, so nothing jumps when a radius crosses 0.5 (at
  r = 0.5 the splat is within 0.07 per pixel of the disc's exact coverage anyway).

Error bounds, measured against exact areas over radii 0.5 to 200 px at random sub-pixel
positions (tests/test_splat.py checks each one with a margin):
  per pixel   |c - c_exact| <= 0.06 / r for r >= 1 (0.043 at r = 1, 0.0055 at 10, 0.0003 at
              200); <= 0.075 for 0.5 <= r < 1
  area        exact (to rounding) for r < 4; within 0.1 px^2 for r >= 4 (0.16 % at r = 4,
              2e-6 relative at r = 200)
  centroid    within 0.06 / r px of the centre for r >= 1, 0.09 px for 0.5 <= r < 1, exact
              below (exact areas are themselves off by up to 0.06 px at r = 0.5, 0.02/r above)
  untouched   a pixel the disc does not reach is not touched, for r >= BLEND; the splat below
              reaches the four pixels around the centre by design

Rings (the annulus between r - t/2 and r + t/2, what cv2.circle draws with thickness t) are the
outer disc's fractions minus the inner disc's, each as above, so an annulus covers
pi ((r + t/2)^2 - (r - t/2)^2) within the sum of the two discs' bounds.

The kernels take any (h, w, k) canvas: a uint8 frame (the blend rounds: bias = 0.5) or a float
one (bias 0), which is how the tests read the fractions themselves (`disc_coverage`).
"""
from __future__ import annotations

import math

import numpy as np
from numba import njit

TINY = 0.5        # below this radius a disc is a bilinear splat of its area
BLEND = 1.0 / math.sqrt(math.pi)   # from TINY to here (area 1) mixed with that splat
SMALL = 4.0       # below this radius a disc's fractions are normalized to sum to pi r^2
SCRATCH = 12      # a disc of radius < SMALL spans at most 2 * SMALL + 2 pixels
ONE_TWELFTH = 1.0 / 12.0
INSIDE = 2.0      # the scratch's mark for a pixel entirely inside a disc


@njit(cache=True, inline="always", error_model="numpy")
def _centred(r):
    """Exact covered fraction of the pixel centred on a disc of radius r >= 0.5."""
    if r * r >= 0.5:
        return 1.0
    segment = r * r * math.acos(0.5 / r) - 0.5 * math.sqrt(r * r - 0.25)
    return math.pi * r * r - 4.0 * segment


@njit(cache=True, inline="always", error_model="numpy")
def _edge(dx, dy, r, rs):
    """Covered fraction of a boundary pixel whose centre is at (dx, dy) from the centre of a
    disc of radius r: the exact area of the unit square inside the tangent line at distance rs
    (= sqrt(r^2 - 1/12)) from the disc's centre, normal (dx, dy) / d.

    The square's projection on the unit normal (a, b) = (max, min of |dx|, |dy|) / d is a
    trapezoid: flat over |u| <= (a - b)/2, linear tails to (a + b)/2. Its CDF at s = rs - d is
    0.5 + s/a on the flat part and 1 - (e - |s|)^2 / (2ab) (mirrored for s < 0) on the tails.
    Both sides are multiplied by d (sd = s d) so that one division and one square root suffice."""
    ax, ay = abs(dx), abs(dy)
    m, k = max(ax, ay), min(ax, ay)
    if m < 1e-9:
        return _centred(r)
    d = math.sqrt(ax * ax + ay * ay)
    s = rs - d
    if k <= 1e-9 * m:                      # an axis-aligned normal: the unit ramp
        return min(max(0.5 + s, 0.0), 1.0)
    sd = s * d
    inverse = 1.0 / (m * k)
    flat = 0.5 + sd * k * inverse          # 0.5 + s / a
    u = max(0.5 * (m + k) - abs(sd), 0.0)  # (e - |s|) d
    tail = 0.5 * u * u * inverse           # (e - |s|)^2 / (2ab)
    return flat if abs(sd) <= 0.5 * (m - k) else (1.0 - tail if sd >= 0.0 else tail)


@njit(cache=True, inline="always", error_model="numpy")
def _shifted(r):
    return math.sqrt(max(r * r - ONE_TWELFTH, 0.0))


@njit(cache=True, inline="always", error_model="numpy")
def _row(cx, dy, r):
    """For the pixel row at dy from the centre: the columns the disc touches, (first, last),
    and the columns entirely inside it, (first, last), unclipped floats. An empty run of
    inside columns is (last touched + 1, last touched); an untouched row is (1, 0, 1, 0)."""
    ey = max(abs(dy) - 0.5, 0.0)
    if ey >= r:
        return 1.0, 0.0, 1.0, 0.0
    p = math.sqrt(r * r - ey * ey)
    t0 = math.floor(cx - p - 0.5) + 1.0
    t1 = math.ceil(cx + p + 0.5) - 1.0
    fy = abs(dy) + 0.5
    rest = r * r - fy * fy
    if rest >= 0.0:
        q = math.sqrt(rest) - 0.5
        if q >= 0.0:
            return t0, t1, math.ceil(cx - q), math.floor(cx + q)
    return t0, t1, t1 + 1.0, t1


@njit(cache=True, inline="always", error_model="numpy")
def _clip(x, lo, hi):
    return int(min(max(x, lo), hi))


@njit(cache=True, inline="always", error_model="numpy")
def _runs(t0, t1, o0, o1, width):
    """Clip a row's touched columns [t0, t1] to the canvas and split them around the run
    [o0, o1] (empty: o0 = o1 + 1): returns a, before, run0, run1, after, b with [a, before] and
    [after, b] the columns left and right of the run, [run0, run1] the run's columns."""
    w = float(width)
    a = _clip(t0, 0.0, w)
    b = _clip(t1, -1.0, w - 1.0)
    before = min(_clip(o0 - 1.0, -1.0, w), b)
    run0 = max(_clip(o0, -1.0, w), a)
    run1 = min(_clip(o1, -1.0, w), b)
    after = max(_clip(o1 + 1.0, -1.0, w), a)
    return a, before, run0, run1, after, b


@njit(cache=True, inline="always", error_model="numpy")
def _blend(canvas, j, i, colors, n, c, bias):
    if colors.shape[1] == 3:      # a frame: written out, which compiles to much faster code
        v = canvas[j, i, 0]
        canvas[j, i, 0] = v + (colors[n, 0] - v) * c + bias
        v = canvas[j, i, 1]
        canvas[j, i, 1] = v + (colors[n, 1] - v) * c + bias
        v = canvas[j, i, 2]
        canvas[j, i, 2] = v + (colors[n, 2] - v) * c + bias
    else:
        for k in range(colors.shape[1]):
            v = canvas[j, i, k]
            canvas[j, i, k] = v + (colors[n, k] - v) * c + bias


@njit(cache=True, inline="always", error_model="numpy")
def _fill(canvas, j, i0, i1, colors, n, bias):
    if colors.shape[1] == 3:
        b, g, r = colors[n, 0] + bias, colors[n, 1] + bias, colors[n, 2] + bias
        for i in range(i0, i1 + 1):
            canvas[j, i, 0] = b
            canvas[j, i, 1] = g
            canvas[j, i, 2] = r
    else:
        for i in range(i0, i1 + 1):
            for k in range(colors.shape[1]):
                canvas[j, i, k] = colors[n, k] + bias


@njit(cache=True, inline="always", error_model="numpy")
def _tent(canvas, cx, cy, area, colors, n, bias):
    """A sub-pixel disc: its area spread bilinearly over the four pixels around (cx, cy)."""
    height, width = canvas.shape[0], canvas.shape[1]
    i0 = int(math.floor(cx))
    j0 = int(math.floor(cy))
    wx1 = cx - i0
    wy1 = cy - j0
    for dj in range(2):
        j = j0 + dj
        if j < 0 or j >= height:
            continue
        wy = area * (wy1 if dj else 1.0 - wy1)
        for di in range(2):
            i = i0 + di
            if i < 0 or i >= width:
                continue
            c = wy * (wx1 if di else 1.0 - wx1)
            if c > 0.0:
                _blend(canvas, j, i, colors, n, min(c, 1.0), bias)


@njit(cache=True, error_model="numpy")
def _small_cover(cx, cy, r, scratch):
    """A disc of radius in [TINY, SMALL): the raw covered fractions of its box (INSIDE for the
    pixels entirely inside) into scratch[:h, :w], and the affine map c -> alpha c + beta for
    its boundary fractions (c > 0) that makes all its fractions sum to pi r^2: a scaling
    towards 0 when they sum too high, towards 1 when too low, so no fraction leaves [0, 1].
    Returns (i0, j0, w, h, alpha, beta), (i0, j0) the box's first pixel."""
    rs = _shifted(r)
    r2 = r * r
    i0 = math.floor(cx - r + 0.5)
    j0 = math.floor(cy - r + 0.5)
    w = int(math.floor(cx + r + 0.5) - i0) + 1
    h = int(math.floor(cy + r + 0.5) - j0) + 1
    inside = 0.0
    total = 0.0
    count = 0.0
    for jj in range(h):
        dy = j0 + jj - cy
        ny = max(abs(dy) - 0.5, 0.0)
        fy = abs(dy) + 0.5
        for ii in range(w):
            dx = i0 + ii - cx
            nx = max(abs(dx) - 0.5, 0.0)
            fx = abs(dx) + 0.5
            c = 0.0
            if nx * nx + ny * ny < r2:
                if fx * fx + fy * fy <= r2:
                    c = INSIDE
                    inside += 1.0
                else:
                    c = _edge(dx, dy, r, rs)
                    if c > 0.0:
                        total += c
                        count += 1.0
            scratch[jj, ii] = c
    target = math.pi * r2 - inside
    if total >= target:
        alpha, beta = (target / total if total > 0.0 else 1.0), 0.0
    else:
        keep = max((count - target) / (count - total), 0.0) if count > total else 0.0
        alpha, beta = keep, 1.0 - keep
    return int(i0), int(j0), w, h, alpha, beta


@njit(cache=True, inline="always", error_model="numpy")
def _tent_weight(dx, dy, r):
    """Fraction of a disc's area pi r^2 that a bilinear splat gives the pixel at (dx, dy)."""
    return math.pi * r * r * max(1.0 - abs(dx), 0.0) * max(1.0 - abs(dy), 0.0)


@njit(cache=True, inline="always", error_model="numpy")
def _mixed(c, dx, dy, r):
    """Below BLEND, the fraction c mixed with the bilinear splat, all splat at TINY."""
    if r >= BLEND:
        return c
    w = (r - TINY) / (BLEND - TINY)
    return w * c + (1.0 - w) * _tent_weight(dx, dy, r)


@njit(cache=True, inline="always", error_model="numpy")
def _small_disc(canvas, cx, cy, r, colors, n, bias, scratch):
    height, width = canvas.shape[0], canvas.shape[1]
    i0, j0, w, h, alpha, beta = _small_cover(cx, cy, r, scratch)
    for jj in range(max(-j0, 0), min(h, height - j0)):
        for ii in range(max(-i0, 0), min(w, width - i0)):
            c = scratch[jj, ii]
            if c > 1.0:
                c = 1.0
            elif c > 0.0:
                c = min(alpha * c + beta, 1.0)
            c = _mixed(c, i0 + ii - cx, j0 + jj - cy, r)
            if c > 0.0:
                _blend(canvas, j0 + jj, i0 + ii, colors, n, min(c, 1.0), bias)


@njit(cache=True, error_model="numpy")
def _large_disc(canvas, cx, cy, r, colors, n, bias):
    """A disc of radius >= SMALL, row by row: the inside run filled, the boundary blended."""
    height, width = canvas.shape[0], canvas.shape[1]
    rs = _shifted(r)
    j0 = _clip(math.floor(cy - r - 0.5) + 1.0, 0.0, height - 1.0)
    j1 = _clip(math.ceil(cy + r + 0.5) - 1.0, 0.0, height - 1.0)
    for j in range(j0, j1 + 1):
        dy = j - cy
        t0, t1, o0, o1 = _row(cx, dy, r)
        a, before, run0, run1, after, b = _runs(t0, t1, o0, o1, width)
        for i in range(a, before + 1):
            c = _edge(i - cx, dy, r, rs)
            if c > 0.0:
                _blend(canvas, j, i, colors, n, c, bias)
        _fill(canvas, j, run0, run1, colors, n, bias)
        for i in range(after, b + 1):
            c = _edge(i - cx, dy, r, rs)
            if c > 0.0:
                _blend(canvas, j, i, colors, n, c, bias)


@njit(cache=True, inline="always", error_model="numpy")
def _disc(canvas, cx, cy, r, colors, n, bias, scratch):
    if r < TINY:
        _tent(canvas, cx, cy, math.pi * r * r, colors, n, bias)
    elif r < SMALL:
        _small_disc(canvas, cx, cy, r, colors, n, bias, scratch)
    else:
        _large_disc(canvas, cx, cy, r, colors, n, bias)


@njit(cache=True, error_model="numpy")
def _off_canvas(cx, cy, r, width, height):
    return not (math.isfinite(cx) and math.isfinite(cy) and math.isfinite(r)) or (
        cx + r + 1.0 < 0.0 or cy + r + 1.0 < 0.0 or cx - r - 1.0 > width or cy - r - 1.0 > height)


@njit(cache=True, error_model="numpy")
def splat_discs(canvas, centres, radii, colors, bias):
    """Draw discs into canvas (h, w, k), in order. centres (n, 2) float pixels, radii (n,) pixels,
    colors (n, >= k) in the canvas's channel order, bias 0.5 for integer canvases (rounding), 0.0
    for float ones. Discs with a non-finite centre or radius, or radius <= 0, are skipped."""
    height, width = canvas.shape[0], canvas.shape[1]
    scratch = np.empty((SCRATCH, SCRATCH))
    for n in range(centres.shape[0]):
        cx, cy, r = centres[n, 0], centres[n, 1], radii[n]
        if r > 0.0 and not _off_canvas(cx, cy, r, width, height):
            _disc(canvas, cx, cy, r, colors, n, bias, scratch)


@njit(cache=True, error_model="numpy")
def _fraction(dx, dy, r, rs, alpha, beta):
    """Covered fraction of the pixel at (dx, dy) from the centre of a disc of radius r (rs and
    the normalizing map alpha, beta as _small_cover gives them)."""
    if r < TINY:
        return _tent_weight(dx, dy, r)
    nx, ny = max(abs(dx) - 0.5, 0.0), max(abs(dy) - 0.5, 0.0)
    fx, fy = abs(dx) + 0.5, abs(dy) + 0.5
    if nx * nx + ny * ny >= r * r:
        c = 0.0
    elif fx * fx + fy * fy <= r * r:
        c = 1.0
    else:
        c = _edge(dx, dy, r, rs)
        c = min(alpha * c + beta, 1.0) if c > 0.0 else 0.0
    return _mixed(c, dx, dy, r)


@njit(cache=True, error_model="numpy")
def _normalizer(cx, cy, r, scratch):
    if TINY <= r < SMALL:
        _, _, _, _, alpha, beta = _small_cover(cx, cy, r, scratch)
        return alpha, beta
    return 1.0, 0.0


@njit(cache=True, error_model="numpy")
def _ring(canvas, cx, cy, outer, inner, colors, n, bias, scratch):
    height, width = canvas.shape[0], canvas.shape[1]
    if outer < TINY:     # both sub-pixel: one splat of the annulus's area
        _tent(canvas, cx, cy, math.pi * (outer * outer - inner * inner), colors, n, bias)
        return
    rs_out, rs_in = _shifted(outer), _shifted(inner)
    alpha_out, beta_out = _normalizer(cx, cy, outer, scratch)
    alpha_in, beta_in = _normalizer(cx, cy, inner, scratch)
    j0 = _clip(math.floor(cy - outer - 0.5) + 1.0, 0.0, height - 1.0)
    j1 = _clip(math.ceil(cy + outer + 0.5) - 1.0, 0.0, height - 1.0)
    for j in range(j0, j1 + 1):
        dy = j - cy
        t0, t1, _, _ = _row(cx, dy, outer)
        _, _, v0, v1 = _row(cx, dy, inner)
        if inner < TINY:
            v0, v1 = 1.0, 0.0                # no pixel lies inside a sub-pixel disc
        # the columns inside the inner disc stay untouched: visit [a, before] and [after, b]
        a, before, _, _, after, b = _runs(t0, t1, v0, v1, width)
        for part in range(2):
            first, last = (a, before) if part == 0 else (after, b)
            for i in range(first, last + 1):
                dx = i - cx
                c = (_fraction(dx, dy, outer, rs_out, alpha_out, beta_out)
                     - _fraction(dx, dy, inner, rs_in, alpha_in, beta_in))
                if c > 0.0:
                    _blend(canvas, j, i, colors, n, min(c, 1.0), bias)


@njit(cache=True, error_model="numpy")
def splat_rings(canvas, centres, radii, thickness, colors, bias):
    """Draw rings into canvas (h, w, k), in order: the annulus between radii - thickness/2 and
    radii + thickness/2 (each (n,) pixels; an inner radius <= 0 makes a disc, and so does a
    negative thickness: the disc of radius radii, cv2's FILLED). Other arguments as for
    splat_discs."""
    height, width = canvas.shape[0], canvas.shape[1]
    scratch = np.empty((SCRATCH, SCRATCH))
    for n in range(centres.shape[0]):
        cx, cy = centres[n, 0], centres[n, 1]
        half = 0.5 * thickness[n]
        outer, inner = (radii[n], 0.0) if half < 0.0 else (radii[n] + half, radii[n] - half)
        if not (outer > 0.0) or not math.isfinite(inner) or _off_canvas(cx, cy, outer, width, height):
            continue
        if inner <= 0.0:
            _disc(canvas, cx, cy, outer, colors, n, bias, scratch)
        else:
            _ring(canvas, cx, cy, outer, inner, colors, n, bias, scratch)


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
    if colors.shape[1] > canvas.shape[2]:
        raise ValueError(f"{colors.shape[1]} colour channels for a canvas of {canvas.shape[2]}")
    return centres, radii, colors


def draw_discs(canvas, centres_px, radii_px, colors) -> None:
    """Filled anti-aliased discs into canvas (h, w, k) in place, in order, in one compiled call.
    centres_px (n, 2), radii_px (n,) or one radius, colors (n, k) or one (k,) colour in the
    canvas's channel order (BGR for a frame)."""
    centres, radii, colors = _prepare(canvas, centres_px, radii_px, colors)
    if len(centres):
        splat_discs(canvas, centres, radii, colors, _bias(canvas))


def draw_annuli(canvas, centres_px, radii_px, thickness_px, colors) -> None:
    """Anti-aliased rings into canvas in place: annuli of width thickness_px (n,) or one,
    centred on radii_px, as cv2.circle draws outlines; a negative thickness fills the disc of
    radius radii_px (cv2's FILLED). Other arguments as for draw_discs."""
    centres, radii, colors = _prepare(canvas, centres_px, radii_px, colors)
    thickness = np.ascontiguousarray(np.broadcast_to(np.asarray(thickness_px, np.float64), radii.shape))
    if len(centres):
        splat_rings(canvas, centres, radii, thickness, colors, _bias(canvas))


def disc_coverage(shape, centres_px, radii_px) -> np.ndarray:
    """The covered fractions (h, w) float64 of discs drawn alone on an empty canvas of `shape`
    (h, w): what draw_discs blends each pixel by (where the discs do not overlap)."""
    canvas = np.zeros((shape[0], shape[1], 1))
    draw_discs(canvas, centres_px, radii_px, [1.0])
    return canvas[:, :, 0]


def ring_coverage(shape, centres_px, radii_px, thickness_px) -> np.ndarray:
    """As disc_coverage, for rings."""
    canvas = np.zeros((shape[0], shape[1], 1))
    draw_annuli(canvas, centres_px, radii_px, thickness_px, [1.0])
    return canvas[:, :, 0]
