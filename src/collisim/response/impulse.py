"""The two formulas of a two-body contact, written once for every path.

Impulse, from conservation of momentum and Newton's law of restitution. Along the unit normal
n (from i to j), with the approach speed u = (v_j - v_i)·n < 0 and restitution e, the impulse

    J = -(1 + e) · u / (1/m_i + 1/m_j)

gives v_i -= J/m_i · n and v_j += J/m_j · n. For e = 1 this is the video's 2D elastic formula
v_1' = v_1 - 2 m_2/(m_1+m_2) · <v_1 - v_2, x_1 - x_2>/|x_1 - x_2|² · (x_1 - x_2), with both new
velocities computed from the pre-collision ones. Only an approaching pair gets an impulse: one
that overlaps but already separates is left alone.

Push-apart: an overlap is removed by moving the two bodies apart along n, split by inverse mass
(the heavier one moves less). This changes no velocity, so it leaves kinetic energy and
momentum as they are; under gravity it changes potential energy by m·g·Δy, which shows as
energy drift of the discrete method.
"""
from numba import njit


@njit(cache=True, error_model="numpy")
def newton_impulse(approach, restitution, mass):
    """Newton's impulse J = -(1 + e)·u·m for an approach speed u < 0 along the normal and the
    pair's effective mass m = 1 / (1/m_i + 1/m_j)."""
    return -(1.0 + restitution) * approach * mass


@njit(cache=True, error_model="numpy")
def apply_normal_impulse(velocities, masses, i, j, nx, ny, restitution):
    """Give the pair i, j its impulse along the unit normal (nx, ny) from i to j, in place, if
    it is approaching. velocities: (n, 2); masses: (n,). Returns the impulse (0 if none)."""
    inv_i, inv_j = 1.0 / masses[i], 1.0 / masses[j]
    approach = (velocities[j, 0] - velocities[i, 0]) * nx + (velocities[j, 1] - velocities[i, 1]) * ny
    if approach >= 0.0:
        return 0.0
    impulse = newton_impulse(approach, restitution, 1.0 / (inv_i + inv_j))
    velocities[i, 0] -= impulse * inv_i * nx
    velocities[i, 1] -= impulse * inv_i * ny
    velocities[j, 0] += impulse * inv_j * nx
    velocities[j, 1] += impulse * inv_j * ny
    return impulse


@njit(cache=True, error_model="numpy")
def push_apart(positions, masses, i, j, nx, ny, overlap):
    """Move i and j apart along the unit normal (nx, ny) by `overlap` (nothing if <= 0), split
    by inverse mass. positions: (n, 2); masses: (n,)."""
    if overlap <= 0.0:
        return
    inv_i, inv_j = 1.0 / masses[i], 1.0 / masses[j]
    share_i = inv_i / (inv_i + inv_j)
    positions[i, 0] -= overlap * share_i * nx
    positions[i, 1] -= overlap * share_i * ny
    positions[j, 0] += overlap * (1.0 - share_i) * nx
    positions[j, 1] += overlap * (1.0 - share_i) * ny
