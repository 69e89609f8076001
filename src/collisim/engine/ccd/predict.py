"""Event prediction: the next things that will happen to one particle.

A particle's *one-particle* events are: crossing into another cell, hitting a
box wall, hitting a segment, and (when resting on a segment) sliding off its
end. Only the earliest of them is queued: when it happens the particle is
predicted again anyway, so the later ones would be out of date. Its time is the
particle's *horizon*.

A *pair* collision between i and j only needs to be looked for up to the
earlier of the two horizons, for the same reason; and only with the particles
of the 3 × 3 block of cells around i, because the cells are wider than a
diameter and neither particle changes cell before its horizon. The few large
bodies kept out of the cell lists (broadphase/cells.py) are tested from both
sides: i tests each of them whose reach covers its cell, and a large body
tests the block of cells its reach covers.
"""
from ...core.compiling import inlined, kernel
from ...core.geometry.box import wall_geometry
from ...core.geometry.toi import time_to_point, time_to_segment, time_to_wall
from ...core.kinds import N_WALLS, PAIR, SEGMENT, WALL
from .bodies import FREE, position_at, rests_on, velocity_at
from .eventqueue import CELL, SLIDE_OFF, event_key, push
from ...broadphase.cells import cell_bounds, is_apart, reach_block


@kernel
def _earlier(t, kind, j, best_t, best_kind, best_j):
    """The earlier of two candidate events (t, kind, j); ties go to (kind, j).
    A candidate with j = -1 is "nothing found"."""
    if j >= 0 and (t < best_t or (t == best_t and (kind, j) < (best_kind, best_j))):
        return t, kind, j
    return best_t, best_kind, best_j


@inlined
def next_cell_crossing(bodies, grid, i, t_max):
    """(t, direction) of particle i's exit from its cell, t relative to its t_ref.
    Directions 0 -x, 1 +x, 2 -y, 3 +y; the box's outer sides are walls, not exits."""
    c = grid.cell[i]
    cx, cy = c % grid.nx, c // grid.nx
    left, bottom, right, top = cell_bounds(grid, c)
    x, y = bodies.pos[i, 0], bodies.pos[i, 1]
    vx, vy = bodies.vel[i, 0], bodies.vel[i, 1]
    ax, ay = bodies.acc[i, 0], bodies.acc[i, 1]
    best_t, best_direction = t_max, -1
    exits = ((cx > 0, x, vx, ax, left, -1.0), (cx < grid.nx - 1, x, vx, ax, right, 1.0),
             (cy > 0, y, vy, ay, bottom, -1.0), (cy < grid.ny - 1, y, vy, ay, top, 1.0))
    for direction in range(4):
        exists, coordinate, rate, accel, bound, side = exits[direction]
        if exists:
            t = time_to_wall(coordinate, rate, accel, bound, side, best_t)
            if t < best_t:
                best_t, best_direction = t, direction
    return best_t, best_direction


@inlined
def next_wall_hit(bodies, env, i, t_max):
    """(t, wall) of particle i's next box wall impact (not the wall it rests on)."""
    best_t, best_wall = t_max, -1
    for wall in range(N_WALLS):
        if rests_on(bodies, i, wall):
            continue
        axis, bound, inward = wall_geometry(env.box, wall, bodies.radius[i])
        t = time_to_wall(bodies.pos[i, axis], bodies.vel[i, axis], bodies.acc[i, axis], bound, -inward, best_t)
        if t < best_t:
            best_t, best_wall = t, wall
    return best_t, best_wall


@kernel
def next_segment_hit(bodies, segments, listed, first, last, every, i, t_max):
    """(t, segment) of particle i's next impact with a segment near its cell: the segments
    listed[first:last] (the grid's lists, broadphase/cells.py), or segments first .. last - 1
    themselves when `every` (a large body kept apart tests every segment). Arrays and numbers
    rather than the grid and the environment: see predict_solo."""
    best_t, best_segment = t_max, -1
    for k in range(first, last):
        s = k if every else listed[k]
        if rests_on(bodies, i, N_WALLS + s):
            continue
        x0, y0, x1, y1 = segments[s, 0], segments[s, 1], segments[s, 2], segments[s, 3]
        t = time_to_segment(bodies.pos[i, 0], bodies.pos[i, 1], bodies.vel[i, 0], bodies.vel[i, 1],
                            bodies.acc[i, 0], bodies.acc[i, 1], bodies.radius[i], x0, y0, x1, y1, best_t)[0]
        if t < best_t:
            best_t, best_segment = t, s
    return best_t, best_segment


@kernel
def slide_off_time(bodies, segments, i, t_max):
    """When particle i, resting (not wedged) on a segment, slides past one of its end points:
    its coordinate along the segment leaves [0, length] (two 1D walls)."""
    s = bodies.support[i] - N_WALLS
    x0, y0 = segments[s, 0], segments[s, 1]
    ex, ey = segments[s, 2] - x0, segments[s, 3] - y0
    length = (ex * ex + ey * ey) ** 0.5
    ux, uy = ex / length, ey / length
    w = (bodies.pos[i, 0] - x0) * ux + (bodies.pos[i, 1] - y0) * uy
    w_rate = bodies.vel[i, 0] * ux + bodies.vel[i, 1] * uy
    w_acc = bodies.acc[i, 0] * ux + bodies.acc[i, 1] * uy
    return min(time_to_wall(w, w_rate, w_acc, 0.0, -1.0, t_max), time_to_wall(w, w_rate, w_acc, length, 1.0, t_max))


@inlined
def predict_solo(bodies, grid, env, i, t_now, t_end):
    """Particle i's next one-particle event (t, kind, j) — t absolute, j = -1 for none (nothing
    before t_end, or asleep: frozen, nothing happens to it on its own) — for the caller to queue;
    sets its horizon. Particle i must be current (t_ref = t_now).

    The searches also run for a sleeper (nothing moves: they find nothing); their result is
    dropped."""
    limit = t_end - t_now
    asleep = bodies.asleep[i]
    c = grid.cell[i]
    every, segments, listed = is_apart(grid, i), env.segments, grid.segment_index
    first, last = grid.segment_start[c], grid.segment_start[c + 1]
    if every:   # a large body kept apart tests every segment
        first, last = 0, segments.shape[0]
    support, wedge = bodies.support[i], bodies.wedge[i]
    best = (limit, CELL, -1)
    t, direction = next_cell_crossing(bodies, grid, i, limit)
    best = _earlier(t, CELL, direction, *best)
    t, wall = next_wall_hit(bodies, env, i, best[0])
    best = _earlier(t, WALL, wall, *best)
    if last > first:   # only call it when there are segments to test
        t, s = next_segment_hit(bodies, segments, listed, first, last, every, i, best[0])
        best = _earlier(t, SEGMENT, s, *best)
    if support >= N_WALLS and wedge == FREE:
        best = _earlier(slide_off_time(bodies, segments, i, best[0]), SLIDE_OFF, support - N_WALLS, *best)
    t, kind, j = best
    horizon = t_end if asleep else t_now + t
    bodies.horizon[i] = horizon
    return horizon, kind, -1 if asleep else j


@inlined
def predict_pairs(bodies, grid, queue, i, t_now, done, base):
    """Queue particle i's collisions with the particles of its block of cells (3 × 3, or as
    far as a large body reaches) and with the large bodies kept apart that may reach it,
    each up to the earlier of the two horizons, skipping the particles j with done[j] (whose
    pairs were just predicted). i must be current."""
    reach, ci, nx = grid.reach[i], grid.cell[i], grid.nx
    cx_lo, cx_hi, cy_lo, cy_hi = reach_block(grid, ci, reach)
    for cy in range(cy_lo, cy_hi):
        row = cy * nx
        for cx in range(cx_lo, cx_hi):
            j = grid.head[row + cx]
            while j >= 0:
                _predict_pair(bodies, queue, i, j, t_now, done, base)
                j = grid.next[j]
    for k in range(grid.apart.shape[0]):
        j = grid.apart[k]
        cj, reach_j = grid.cell[j], grid.reach[j]   # does this large body reach i's cell?
        if reach > 1 or (abs(ci % nx - cj % nx) <= reach_j and abs(ci // nx - cj // nx) <= reach_j):
            _predict_pair(bodies, queue, i, j, t_now, done, base)


@inlined
def _predict_pair(bodies, queue, i, j, t_now, done, base):
    """Queue the collision of i and j (i current) if it comes before both horizons."""
    if j == i or done[j]:
        return
    xj, yj = position_at(bodies, j, t_now)
    vxj, vyj = velocity_at(bodies, j, t_now)
    t_max = min(bodies.horizon[i], bodies.horizon[j]) - t_now
    t = time_to_point(xj - bodies.pos[i, 0], yj - bodies.pos[i, 1], vxj - bodies.vel[i, 0], vyj - bodies.vel[i, 1],
                      bodies.acc[j, 0] - bodies.acc[i, 0], bodies.acc[j, 1] - bodies.acc[i, 1],
                      bodies.radius[i] + bodies.radius[j], t_max)
    if t <= t_max:
        lo, hi = min(i, j), max(i, j)
        push(queue, t_now + t, event_key(PAIR, lo, hi, base), bodies.counter[lo], bodies.counter[hi])
