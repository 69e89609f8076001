"""Real roots of low-degree polynomials on an interval, by monotone-piece isolation.

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

Coefficients are stored lowest order first: p(t) = c[0] + c[1] t + ... + c[k] t^k.
"""
import numpy as np
from numba import njit

# Enough steps to shrink any finite bracket to two adjacent doubles by bisection
# alone; Newton usually converges in well under ten.
MAX_ITERATIONS = 2200


@njit(cache=True, error_model="numpy")
def evaluate(coeffs, t):
    """p(t) by Horner's rule. coeffs: (k+1,) lowest order first."""
    value = 0.0
    for k in range(coeffs.shape[0] - 1, -1, -1):
        value = value * t + coeffs[k]
    return value


@njit(cache=True, error_model="numpy")
def derivative(coeffs):
    """Coefficients (k,) of p' for coeffs (k+1,); a constant's derivative is (0,)."""
    out = np.zeros(max(coeffs.shape[0] - 1, 1))
    for k in range(1, coeffs.shape[0]):
        out[k - 1] = k * coeffs[k]
    return out


@njit(cache=True, error_model="numpy")
def refine_root(coeffs, slopes, lo, hi):
    """The root of p in [lo, hi], given that p(lo) and p(hi) have opposite signs
    (one may be 0); slopes are the coefficients of p'. Safeguarded Newton."""
    lo_positive = evaluate(coeffs, lo) > 0.0
    t = 0.5 * (lo + hi)
    previous_step = hi - lo
    for _ in range(MAX_ITERATIONS):
        value = evaluate(coeffs, t)
        if value == 0.0:
            return t
        if (value > 0.0) == lo_positive:
            lo = t
        else:
            hi = t
        slope = evaluate(slopes, t)
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


@njit(cache=True, error_model="numpy")
def split_at_sign_changes(coeffs, slopes, breaks):
    """Refine sorted breakpoints (k,) by the roots of p on each piece where p is monotone.

    Returns (lo, roots found, hi) as a new sorted array: the pieces where p keeps its sign.
    """
    out = np.empty(2 * breaks.shape[0])
    out[0] = breaks[0]
    count = 1
    for k in range(breaks.shape[0] - 1):
        a, b = breaks[k], breaks[k + 1]
        if (evaluate(coeffs, a) > 0.0) != (evaluate(coeffs, b) > 0.0):
            out[count] = refine_root(coeffs, slopes, a, b)
            count += 1
    out[count] = breaks[-1]
    return out[:count + 1]


@njit(cache=True, error_model="numpy")
def monotone_pieces(coeffs, lo, hi):
    """Sorted breakpoints lo = b[0] <= ... <= b[-1] = hi with p monotone on each piece.

    The (k-1)-th derivative of a degree-k polynomial is linear, hence monotone on
    [lo, hi]; its sign changes split [lo, hi] into pieces where the (k-2)-th derivative
    is monotone, and so on down to p' itself, whose sign changes are p's turning points.
    """
    degree = coeffs.shape[0] - 1
    derivatives = np.zeros((degree + 1, degree + 1))  # row k: the k-th derivative
    derivatives[0] = coeffs
    for order in range(1, degree + 1):
        derivatives[order, :degree + 1 - order] = derivative(derivatives[order - 1, :degree + 2 - order])
    breaks = np.array([lo, hi])
    for order in range(degree - 1, 0, -1):
        breaks = split_at_sign_changes(derivatives[order, :degree + 1 - order],
                                       derivatives[order + 1, :degree - order], breaks)
    return breaks


@njit(cache=True, error_model="numpy")
def first_down_crossing(coeffs, lo, hi):
    """Earliest t in (lo, hi] where p goes from > 0 to <= 0, or inf if p never does."""
    breaks = monotone_pieces(coeffs, lo, hi)
    for k in range(breaks.shape[0] - 1):
        a, b = breaks[k], breaks[k + 1]
        if evaluate(coeffs, a) > 0.0 and evaluate(coeffs, b) <= 0.0:
            return refine_root(coeffs, derivative(coeffs), a, b)
    return np.inf
