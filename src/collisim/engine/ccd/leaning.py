"""What a body at rest touches and leans on: the geometry sleep.py and carried.py decide with.

Touching is to within SLEEP_GAP of the smaller radius: bodies at rest are never exactly in
contact (each event leaves them an impact's rounding apart), so "touching" needs a tolerance.
What could hold a body up touches it from below: a floor or slope gravity presses it into, or a
body whose centre is lower (held_up, leans_on_a_body); a neighbour at or above its own height
cannot. And a contact gives way when a body leans on another from above, off the vertical but
steeper than LEANS (a neighbour at about its own height presses sideways, it does not lean),
and the lower one is free to slide aside (yields): frictionless, a floor holds a body up, not
in place.
"""
import math

from ...core.compiling import kernel
from ...core.geometry.box import wall_geometry
from ...core.geometry.segment import segment_contact
from ...core.kinds import N_WALLS
from ...broadphase.cells import reach_block, segment_range
from .bodies import position_at

# A support this fraction of the radius away (or closer) counts as touching.
SLEEP_GAP = 1e-3
# A body leans on another below it when their line of centres rises more steeply than this sine
# (about 15 degrees) from the horizontal: a neighbour at about its own height presses it sideways
# but carries none of its weight (a row in a pile).
LEANS = 0.25
# One support carries a body alone only if it is this close (radians) to straight under it.
UPRIGHT = 1e-9


@kernel
def held_up(bodies, grid, env, i, t):
    """Does anything that could hold particle i up touch it at time t (within SLEEP_GAP of its
    radius): a wall or segment that gravity presses it into, or a body whose centre is lower
    than its own? Neighbours at or above its own height cannot."""
    x, y = position_at(bodies, i, t)
    r = bodies.radius[i]
    gx, gy = env.gravity[0], env.gravity[1]
    for wall in range(N_WALLS):
        axis, bound, inward = wall_geometry(env.box, wall, r)
        nx, ny = (inward, 0.0) if axis == 0 else (0.0, inward)
        if abs((x, y)[axis] - bound) <= SLEEP_GAP * r and nx * gx + ny * gy < 0.0:
            return True
    first, last, every = segment_range(grid, i, env.segments.shape[0])
    for k in range(first, last):
        nx, ny, distance = segment_contact(x, y, env.segments[k if every else grid.segment_index[k]])[:3]
        if distance - r <= SLEEP_GAP * r and nx * gx + ny * gy < 0.0:   # n points from the segment towards i
            return True
    return leans_on_a_body(bodies, grid, env, i, t)


@kernel
def leans_on_a_body(bodies, grid, env, i, t):
    """Does particle i at time t touch a body (asleep or not, within SLEEP_GAP) whose centre is
    lower than its own, one it could lean on? A body touching only neighbours at or above its
    own height has nothing to hold it up."""
    x, y = position_at(bodies, i, t)
    cx_lo, cx_hi, cy_lo, cy_hi = reach_block(grid, grid.cell[i], grid.reach[i])
    for cy in range(cy_lo, cy_hi):
        for cx in range(cx_lo, cx_hi):
            j = grid.head[cy * grid.nx + cx]
            while j >= 0:
                if j != i and _below(bodies, env, i, j, x, y, t):
                    return True
                j = grid.next[j]
    for k in range(grid.apart.shape[0]):
        if grid.apart[k] != i and _below(bodies, env, i, grid.apart[k], x, y, t):
            return True
    return False


@kernel
def _below(bodies, env, i, j, x, y, t):
    """Does body j touch i (at x, y) with its centre lower than i's?"""
    xj, yj = position_at(bodies, j, t)
    return touching(bodies, i, j, x, y, xj, yj) and (xj - x) * env.gravity[0] + (yj - y) * env.gravity[1] > 0.0


@kernel
def touching(bodies, i, j, x, y, xj, yj):
    """Does body j (at xj, yj) touch particle i (at x, y), to within SLEEP_GAP of the smaller radius?"""
    gap = math.hypot(x - xj, y - yj) - bodies.radius[i] - bodies.radius[j]
    return gap <= SLEEP_GAP * min(bodies.radius[i], bodies.radius[j])


@kernel
def yields(bodies, grid, env, i, t):
    """Is particle i at time t in a contact that gives way sideways: an awake body leans on it
    from above, off the vertical, and i is free to move aside; or i leans so on an awake body
    that is free to move aside? A frictionless floor holds a body up, not in place: the bottom
    balls of a pyramid are pushed apart by the one on top, and frozen before its weight reaches
    them (or the top frozen while they begin to slide) they would hold it up for ever. So
    neither falls asleep while it lasts: once the leaning body sleeps on sleepers, or the lower
    one is held (free_towards), they may."""
    gravity = math.hypot(env.gravity[0], env.gravity[1])
    ux, uy = -env.gravity[0] / gravity, -env.gravity[1] / gravity
    x, y = position_at(bodies, i, t)
    cx_lo, cx_hi, cy_lo, cy_hi = reach_block(grid, grid.cell[i], grid.reach[i])
    for cy in range(cy_lo, cy_hi):
        for cx in range(cx_lo, cx_hi):
            j = grid.head[cy * grid.nx + cx]
            while j >= 0:
                if j != i and not bodies.asleep[j] and _gives_way(bodies, grid, env, i, j, x, y, t, ux, uy):
                    return True
                j = grid.next[j]
    for k in range(grid.apart.shape[0]):
        j = grid.apart[k]
        if j != i and not bodies.asleep[j] and _gives_way(bodies, grid, env, i, j, x, y, t, ux, uy):
            return True
    return False


@kernel
def _gives_way(bodies, grid, env, i, j, x, y, t, ux, uy):
    """Do awake bodies i (at x, y) and j touch, the upper one leaning on the lower off the
    vertical (up: ux, uy), towards a side where the lower one is free to go?"""
    xj, yj = position_at(bodies, j, t)
    if not touching(bodies, i, j, x, y, xj, yj):
        return False
    dx, dy = x - xj, y - yj
    if dx * ux + dy * uy > 0.0:   # i above: it pushes j along -d
        lower, px, py, dx, dy = j, xj, yj, -dx, -dy
    else:
        lower, px, py = i, x, y
    down = dx * ux + dy * uy
    sx, sy = dx - down * ux, dy - down * uy
    return -down > LEANS * math.hypot(dx, dy) and sx * sx + sy * sy > (UPRIGHT * down) ** 2 and \
        free_towards(bodies, grid, env, lower, px, py, sx, sy, t)


@kernel
def free_towards(bodies, grid, env, i, x, y, dx, dy, t):
    """Could particle i (at x, y at time t) slide along (dx, dy)? Not if anything it touches
    (within SLEEP_GAP of its radius) is in the way: a wall, a segment or a body on that side."""
    r = bodies.radius[i]
    gap = SLEEP_GAP * r
    for wall in range(N_WALLS):
        axis, bound, inward = wall_geometry(env.box, wall, r)
        if abs((x, y)[axis] - bound) <= gap and inward * (dx, dy)[axis] < 0.0:
            return False
    first, last, every = segment_range(grid, i, env.segments.shape[0])
    for k in range(first, last):
        nx, ny, distance = segment_contact(x, y, env.segments[k if every else grid.segment_index[k]])[:3]
        if distance - r <= gap and nx * dx + ny * dy < 0.0:   # n points from the segment towards i
            return False
    cx_lo, cx_hi, cy_lo, cy_hi = reach_block(grid, grid.cell[i], grid.reach[i])
    for cy in range(cy_lo, cy_hi):
        for cx in range(cx_lo, cx_hi):
            j = grid.head[cy * grid.nx + cx]
            while j >= 0:
                if j != i and _in_the_way(bodies, i, j, x, y, dx, dy, t):
                    return False
                j = grid.next[j]
    for k in range(grid.apart.shape[0]):
        j = grid.apart[k]
        if j != i and _in_the_way(bodies, i, j, x, y, dx, dy, t):
            return False
    return True


@kernel
def _in_the_way(bodies, i, j, x, y, dx, dy, t):
    """Does body j touch i (at x, y) on the side of (dx, dy)?"""
    xj, yj = position_at(bodies, j, t)
    return touching(bodies, i, j, x, y, xj, yj) and (xj - x) * dx + (yj - y) * dy > 0.0
