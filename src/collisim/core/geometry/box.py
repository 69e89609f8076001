"""The box: where a circle's centre may be, and on which side it touches a wall.

A circle of radius r touches the left wall when x - r = xmin, so its centre ranges over
[xmin + r, xmax - r] on x (and likewise on y). Walls are numbered 2·axis + side, as in
kinds.WALL_SIDES: 0 left, 1 right, 2 bottom, 3 top.
"""
from ..compiling import kernel


@kernel
def centre_range(box, axis, radius):
    """(low, high): the centre coordinates on `axis` at which a circle of `radius` touches the
    low and the high wall. box: (4,) xmin, ymin, xmax, ymax."""
    return box[axis] + radius, box[axis + 2] - radius


@kernel
def wall_geometry(box, wall, radius):
    """(axis, bound, inward) of a wall: the axis it stops, the centre coordinate of a circle
    touching it, and the sign of its inward normal."""
    axis = wall // 2
    low, high = centre_range(box, axis, radius)
    if wall % 2 == 0:
        return axis, low, 1.0
    return axis, high, -1.0


@kernel
def clamp_into_box(positions, radii, box):
    """Put every circle inside the box, positions only. positions: (n, 2); radii: (n,)."""
    for i in range(positions.shape[0]):
        for axis in range(2):
            low, high = centre_range(box, axis, radii[i])
            positions[i, axis] = min(max(positions[i, axis], low), high)
