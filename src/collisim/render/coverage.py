"""How much of a pixel a disc covers: the fractions the compiled rasterizer (splat.py) blends by.

A pixel (i, j) is the unit square centred on (i, j) (OpenCV's convention); c is the fraction of
that square a disc of radius r covers.

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
"""
from __future__ import annotations

import math

from ..core.compiling import compiled

TINY = 0.5        # below this radius a disc is a bilinear splat of its area
BLEND = 1.0 / math.sqrt(math.pi)   # from TINY to here (area 1) mixed with that splat
SMALL = 4.0       # below this radius a disc's fractions are normalized to sum to pi r^2
SCRATCH = 12      # a disc of radius < SMALL spans at most 2 * SMALL + 2 pixels
ONE_TWELFTH = 1.0 / 12.0
INSIDE = 2.0      # the scratch's mark for a pixel entirely inside a disc


@compiled(inline="always", error_model="numpy")
def _centred(r):
    """Exact covered fraction of the pixel centred on a disc of radius r >= 0.5."""
    if r * r >= 0.5:
        return 1.0
    segment = r * r * math.acos(0.5 / r) - 0.5 * math.sqrt(r * r - 0.25)
    return math.pi * r * r - 4.0 * segment


@compiled(inline="always", error_model="numpy")
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


@compiled(inline="always", error_model="numpy")
def _shifted(r):
    return math.sqrt(max(r * r - ONE_TWELFTH, 0.0))


@compiled(inline="always", error_model="numpy")
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


@compiled(error_model="numpy")
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


@compiled(inline="always", error_model="numpy")
def _normalized(c, alpha, beta):
    """A fraction from _small_cover's scratch mapped by its (alpha, beta): INSIDE becomes 1."""
    if c > 1.0:
        return 1.0
    if c > 0.0:
        return min(alpha * c + beta, 1.0)
    return c


@compiled(inline="always", error_model="numpy")
def _tent_weight(dx, dy, r):
    """Fraction of a disc's area pi r^2 that a bilinear splat gives the pixel at (dx, dy)."""
    return math.pi * r * r * max(1.0 - abs(dx), 0.0) * max(1.0 - abs(dy), 0.0)


@compiled(inline="always", error_model="numpy")
def _mixed(c, dx, dy, r):
    """Below BLEND, the fraction c mixed with the bilinear splat, all splat at TINY."""
    if r >= BLEND:
        return c
    w = (r - TINY) / (BLEND - TINY)
    return w * c + (1.0 - w) * _tent_weight(dx, dy, r)


@compiled(error_model="numpy")
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


@compiled(error_model="numpy")
def _normalizer(cx, cy, r, scratch):
    if TINY <= r < SMALL:
        _, _, _, _, alpha, beta = _small_cover(cx, cy, r, scratch)
        return alpha, beta
    return 1.0, 0.0

