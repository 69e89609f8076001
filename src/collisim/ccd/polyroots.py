"""Real roots of low-degree polynomials on an interval, by monotone-piece isolation.

Time of impact under constant acceleration leads to polynomial equations of degree
up to four: |d + v t + a t²/2|² = R² is a quartic in t. The closed-form quartic
(Ferrari) loses most of its digits exactly where collision detection needs them,
near double roots (grazing contacts). This module uses a simple robust scheme:

* between two consecutive real roots of p', the polynomial p is monotone, so it has
  at most one root there, and bisection finds it to the last bit;
* the roots of p' are found the same way from the pieces where p' is monotone, that
  is from the roots of p'', and so on down to a linear derivative.

Coefficients are stored lowest order first: p(t) = c[0] + c[1] t + ... + c[k] t^k.
"""
import numpy as np
from numba import njit

# Enough halvings to shrink any finite bracket to two adjacent doubles (a root in
# [0, 1] typically needs about 60; the loop stops as soon as the bracket can't shrink).
MAX_BISECTIONS = 2200


@njit(cache=True)
def evaluate(coeffs, t):
    """p(t) by Horner's rule. coeffs: (k+1,) lowest order first."""
    value = 0.0
    for k in range(coeffs.shape[0] - 1, -1, -1):
        value = value * t + coeffs[k]
    return value


@njit(cache=True)
def derivative(coeffs):
    """Coefficients (k,) of p' for coeffs (k+1,); a constant's derivative is (0,)."""
    out = np.zeros(max(coeffs.shape[0] - 1, 1))
    for k in range(1, coeffs.shape[0]):
        out[k - 1] = k * coeffs[k]
    return out


@njit(cache=True)
def bisect(coeffs, lo, hi):
    """A root of p in [lo, hi], given that p(lo) > 0 and p(hi) <= 0 or the reverse.

    Returns the end of the final (one-ulp) bracket that has the sign of p(hi): for a
    downward crossing that is the first representable time with p <= 0.
    """
    lo_positive = evaluate(coeffs, lo) > 0.0
    for _ in range(MAX_BISECTIONS):
        mid = 0.5 * (lo + hi)
        if mid <= lo or mid >= hi:
            break
        if (evaluate(coeffs, mid) > 0.0) == lo_positive:
            lo = mid
        else:
            hi = mid
    return hi


@njit(cache=True)
def split_at_sign_changes(coeffs, breaks):
    """Refine sorted breakpoints (k,) by the roots of p on each piece where p is monotone.

    Returns (lo, roots found, hi) as a new sorted array: the pieces where p keeps its sign.
    """
    out = np.empty(2 * breaks.shape[0])
    out[0] = breaks[0]
    count = 1
    for k in range(breaks.shape[0] - 1):
        a, b = breaks[k], breaks[k + 1]
        if (evaluate(coeffs, a) > 0.0) != (evaluate(coeffs, b) > 0.0):
            out[count] = bisect(coeffs, a, b)
            count += 1
    out[count] = breaks[-1]
    return out[:count + 1]


@njit(cache=True)
def monotone_pieces(coeffs, lo, hi):
    """Sorted breakpoints lo = b[0] <= ... <= b[-1] = hi with p monotone on each piece.

    The (k-1)-th derivative of a degree-k polynomial is linear, hence monotone on
    [lo, hi]; its sign changes split [lo, hi] into pieces where the (k-2)-th derivative
    is monotone, and so on down to p' itself, whose sign changes are p's turning points.
    """
    degree = coeffs.shape[0] - 1
    derivatives = [coeffs]
    for _ in range(degree - 1):
        derivatives.append(derivative(derivatives[-1]))
    breaks = np.array([lo, hi])
    for order in range(degree - 1, 0, -1):
        breaks = split_at_sign_changes(derivatives[order], breaks)
    return breaks


@njit(cache=True)
def first_down_crossing(coeffs, lo, hi):
    """Earliest t in (lo, hi] where p goes from > 0 to <= 0, or inf if p never does."""
    breaks = monotone_pieces(coeffs, lo, hi)
    for k in range(breaks.shape[0] - 1):
        a, b = breaks[k], breaks[k + 1]
        if evaluate(coeffs, a) > 0.0 and evaluate(coeffs, b) <= 0.0:
            return bisect(coeffs, a, b)
    return np.inf
