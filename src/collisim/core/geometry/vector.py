"""The length of a 2-D vector, as the engines' inner loops and swept tests compute it.

math.hypot (and np.hypot) guard against overflow and underflow of the squares, and cost about
18 ns a call here against 3 ns for sqrt(x² + y²): the polygon narrow phase takes a length per
edge of both shapes, a dozen per pair, so hypot was most of its time. The squares overflow only
for lengths beyond 1e154 and lose precision only below 1e-154, scales no world reaches (a
circle's own distance test, geometry/circle.py, has always squared).
"""
import math

from ..compiling import kernel


@kernel
def length(x, y):
    """|(x, y)|."""
    return math.sqrt(x * x + y * y)
