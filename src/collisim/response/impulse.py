"""Newton's impulse for two bodies meeting, written once for every path (the discrete solver's
impacts, response/solver.py).

From conservation of momentum and Newton's law of restitution: along the unit normal n (from i
to j), with the approach speed u = (v_j - v_i)·n < 0, restitution e and the pair's effective
mass m = 1 / (1/m_i + 1/m_j) (with the turning terms for bodies that turn), the impulse

    J = -(1 + e) · u · m

gives v_i -= J/m_i · n and v_j += J/m_j · n. For e = 1 and two discs this is the video's 2D
elastic formula v_1' = v_1 - 2 m_2/(m_1+m_2) · <v_1 - v_2, x_1 - x_2>/|x_1 - x_2|² · (x_1 - x_2),
with both new velocities computed from the pre-collision ones.
"""
from ..core.compiling import kernel


@kernel
def newton_impulse(approach, restitution, mass):
    """Newton's impulse J = -(1 + e)·u·m for an approach speed u < 0 along the normal and the
    pair's effective mass m = 1 / (1/m_i + 1/m_j)."""
    return -(1.0 + restitution) * approach * mass
