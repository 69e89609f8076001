"""Circle against circle: they touch when the distance between their centres is at most the
sum of their radii. The contact normal is the line of centres from i to j."""
from ..core.compiling import kernel

from ..core.geometry.circle import line_of_centres


@kernel
def circles_touch(positions, radii, i, j):
    """Do circles i and j overlap or touch? Compared squared: no square root needed.
    positions: (n, 2); radii: (n,)."""
    dx = positions[j, 0] - positions[i, 0]
    dy = positions[j, 1] - positions[i, 1]
    reach = radii[i] + radii[j]
    return dx * dx + dy * dy <= reach * reach


@kernel
def circle_circle(positions, radii, i, j):
    """The contact of circles i and j as (nx, ny, depth, px, py): the unit normal from i to j,
    the overlap depth (negative when apart) and the contact point on i's surface."""
    nx, ny, distance = line_of_centres(positions, i, j)
    depth = radii[i] + radii[j] - distance
    return nx, ny, depth, positions[i, 0] + nx * radii[i], positions[i, 1] + ny * radii[i]
