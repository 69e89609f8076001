"""Two circles: the line of centres, along which they touch and push."""
import math

from ..compiling import kernel


@kernel
def line_of_centres(positions, i, j):
    """(nx, ny, distance): the unit normal from centre i to centre j and their distance.
    positions: (n, 2). Coincident centres have no line of centres: +x is picked, so the
    result is still deterministic."""
    nx = positions[j, 0] - positions[i, 0]
    ny = positions[j, 1] - positions[i, 1]
    distance = math.sqrt(nx * nx + ny * ny)
    if distance == 0.0:
        return 1.0, 0.0, 0.0
    return nx / distance, ny / distance, distance
