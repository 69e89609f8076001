"""Real roots of a quartic on an interval, by monotone-piece isolation, allocating nothing.

Time of impact under constant acceleration leads to polynomial equations of degree
up to four: |d + v t + a t²/2|² = R² is a quartic in t. The closed-form quartic
(Ferrari) loses most of its digits exactly where collision detection needs them,
near double roots (grazing contacts). This module uses a simple robust scheme:

* between two consecutive real roots of p', the polynomial p is monotone, so it has
  at most one root there, and a bracketed search finds it to the last bit;
* the roots of p' are found the same way from the pieces where p' is monotone, that
  is from the roots of p'', and so on down to a linear derivative.

The bracketed search is Newton's method kept inside the bracket: whenever a Newton
step would leave the bracket or does not shrink fast enough, it bisects instead
(rtsafe, Numerical Recipes 9.4). Near a simple root it converges like Newton, and
it is never slower than bisection.

A polynomial is a tuple of five coefficients, lowest order first, p(t) = c[0] + c[1] t
+ ... + c[4] t⁴, with its degree alongside (the coefficients above it are ignored). The
breakpoints between monotone pieces — at most five for a quartic: the ends and three
turning points — are a tuple of five too, with their count. Tuples are indexed only by
constants (`_nth`, `_with`): nothing here allocates or can raise, so the event loop's
predictions, which solve a quartic for every pair of bodies with different accelerations,
call it without reference counting (engine/ccd/events.py).
"""
import numpy as np

from ..compiling import kernel

# Enough steps to shrink any finite bracket to two adjacent doubles by bisection
# alone; Newton usually converges in well under ten.
MAX_ITERATIONS = 2200


@kernel
def evaluate(coeffs, degree, t):
    """p(t) by Horner's rule. coeffs: 5 coefficients, lowest order first; degree <= 4."""
    value = 0.0
    if degree >= 4:
        value = value * t + coeffs[4]
    if degree >= 3:
        value = value * t + coeffs[3]
    if degree >= 2:
        value = value * t + coeffs[2]
    if degree >= 1:
        value = value * t + coeffs[1]
    return value * t + coeffs[0]


@kernel
def derivative(coeffs):
    """The coefficients of p' (one degree less; a constant's derivative is 0)."""
    return coeffs[1], 2.0 * coeffs[2], 3.0 * coeffs[3], 4.0 * coeffs[4], 0.0


@kernel
def refine_root(coeffs, degree, lo, hi):
    """The root of p in [lo, hi], given that p(lo) and p(hi) have opposite signs
    (one may be 0). Safeguarded Newton."""
    slopes, slope_degree = derivative(coeffs), max(degree - 1, 0)
    lo_positive = evaluate(coeffs, degree, lo) > 0.0
    t = 0.5 * (lo + hi)
    previous_step = hi - lo
    for _ in range(MAX_ITERATIONS):
        value = evaluate(coeffs, degree, t)
        if value == 0.0:
            return t
        if (value > 0.0) == lo_positive:
            lo = t
        else:
            hi = t
        slope = evaluate(slopes, slope_degree, t)
        step = value / slope if slope != 0.0 else np.inf
        if abs(2.0 * step) < previous_step and lo < t - step < hi:
            next_t = t - step
        else:
            next_t = 0.5 * (lo + hi)
        previous_step = abs(next_t - t)
        if next_t == t:
            break
        t = next_t
    return t


@kernel
def _nth(points, k):
    """points[k] for k in 0 .. 4, by constant indices only."""
    if k == 0:
        return points[0]
    if k == 1:
        return points[1]
    if k == 2:
        return points[2]
    if k == 3:
        return points[3]
    return points[4]


@kernel
def _with(points, k, x):
    """points with points[k] = x, k in 0 .. 4."""
    a, b, c, d, e = points
    if k == 0:
        return x, b, c, d, e
    if k == 1:
        return a, x, c, d, e
    if k == 2:
        return a, b, x, d, e
    if k == 3:
        return a, b, c, x, e
    return a, b, c, d, x


@kernel
def split_at_sign_changes(coeffs, degree, breaks, count):
    """Refine the sorted breakpoints breaks[:count] by the roots of p on each piece where p
    is monotone: returns (new breaks, their count) = (lo, the roots found, hi), the pieces
    where p keeps its sign."""
    out = (breaks[0], 0.0, 0.0, 0.0, 0.0)
    found = 1
    for k in range(count - 1):
        a, b = _nth(breaks, k), _nth(breaks, k + 1)
        if (evaluate(coeffs, degree, a) > 0.0) != (evaluate(coeffs, degree, b) > 0.0):
            out = _with(out, found, refine_root(coeffs, degree, a, b))
            found += 1
    return _with(out, found, _nth(breaks, count - 1)), found + 1


@kernel
def monotone_pieces(coeffs, lo, hi):
    """Breakpoints (5-tuple, count) lo = b[0] <= ... <= b[count - 1] = hi with the quartic p
    monotone on each piece.

    p''' is linear, hence monotone on [lo, hi]; its sign changes split [lo, hi] into pieces
    where p'' is monotone; the sign changes of p'' split it where p' is, and the sign changes
    of p' are p's turning points."""
    first = derivative(coeffs)
    second = derivative(first)
    third = derivative(second)
    breaks, count = split_at_sign_changes(third, 1, (lo, hi, 0.0, 0.0, 0.0), 2)
    breaks, count = split_at_sign_changes(second, 2, breaks, count)
    return split_at_sign_changes(first, 3, breaks, count)


@kernel
def first_down_crossing(coeffs, lo, hi):
    """Earliest t in (lo, hi] where the quartic p (coeffs: 5, lowest order first) goes from
    > 0 to <= 0, or inf if it never does."""
    breaks, count = monotone_pieces(coeffs, lo, hi)
    for k in range(count - 1):
        a, b = _nth(breaks, k), _nth(breaks, k + 1)
        if evaluate(coeffs, 4, a) > 0.0 and evaluate(coeffs, 4, b) <= 0.0:
            return refine_root(coeffs, 4, a, b)
    return np.inf
