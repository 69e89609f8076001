"""Fast polygons in the discrete step: wall impacts met when they happen, and pairs too fast to follow flagged.

A polygon's wall rows (response/rows.py) are found where the step starts, and the solve takes
an impact there, at the start of the step. For a polygon whose step reaches farther than its
own size that fails: a step that reaches both walls of the box takes both impacts at once,
back and forth, and the solve then stops the body dead between them (a box at 50 sizes a frame,
e = 1, lost all its energy at the first wall and picked up spin). So a *swept* polygon — one
that moves farther than its bounding radius in the step (its speculative margin is capped
there), alone (in no pair's manifold, no segment within its reach), bouncing (e > 0) — has no
wall rows; its step is flown here instead, from its pose at the start of the step, each wall
met at its time of impact:

* conservative advancement: each vertex's distance to each wall is bounded below by
  gap + rate·t + bend·t², with the vertex's rate along the normal now and bend half the
  normal acceleration less ω²·|arm| (the most turning can bend a vertex's path), so the
  flight advances to that bound's first root, exactly the time of impact for a body that does
  not turn, and converging on it for one that does;
* at a touch (within TOUCH of the body's size), Newton's impulse at the touching point (the
  middle of two touching vertices: a face meeting a wall flat turns nothing) with the
  restitution, and Coulomb friction, keeping energy at e = 1, then the rest of the step;
* a touch that cannot be followed (a body resting on a wall, a slow bounce under gravity, more
  than MAX_ADVANCES advances) ends the flight: the rest of the step flown freely, the body put
  back on the wall with its velocity into it removed.

Pairs: two bodies' speculative rows hold them only while what they close in a step stays within
the sum of their margins. A pair with a polygon whose relative travel in the step exceeds that,
and whose bounding circles come within reach of each other during the step, may pass through
each other unseen: its step is flagged approximate (Trajectory.approximate), and the run says
so once (fast_note).

All of it is compiled for worlds with polygons alone (polygons None: no-ops, as in
narrowphase/manifold.py).
"""
import math
from collections import namedtuple

import numpy as np
from numba.core import types
from numba.extending import overload

from ..core.compiling import compiled, inlined, kernel
from ..core.geometry.vector import length
from ..core.kinds import CIRCLE, POLYGON, WALL
from .eventlog import append, with_room

TOUCH = 1e-9          # of the body's bounding radius: a vertex this close to a wall touches it
MAX_ADVANCES = 1000   # advances and impacts a step; beyond, the flight ends put back on the wall
STALL = 1e-12         # of the step: an advance this short cannot be followed

Fast = namedtuple("Fast", ["swept", "count", "start", "outpaced", "reach"])
Fast.__doc__ = """The swept polygons of the coming step, swept[:count[0]] (n,) int64; their poses at the
start of the step, start (n, 6) (x, y, vx, vy, θ, ω); outpaced (2,) int64: how many steps of the
block were flagged for a pair too fast to follow, and the frame of the first (in the block);
reach (n,): segment_reach's."""


def new_fast(n: int) -> Fast:
    return Fast(np.empty(n, np.int64), np.zeros(1, np.int64), np.empty((n, 6)), np.zeros(2, np.int64), np.empty(n))


def fast_note(frame: int) -> str:
    """What a run says (once) when its first frame with a pair too fast to follow is `frame`."""
    return (f"bodies met faster than the discrete step can follow (a polygon moving farther in a step than its "
            f"speculative margin covers), first at frame {frame}; they may pass through each other: use more "
            f"substeps")


@inlined
def _reach(b, dt, i):
    """How far any point of body i can move in a step of dt (response/rows.py's travel)."""
    speed = length(b.velocities[i, 0], b.velocities[i, 1]) + abs(b.angular_velocities[i]) * b.radii[i]
    return speed * dt + length(b.accelerations[i, 0], b.accelerations[i, 1]) * dt * dt


@kernel
def _near_a_segment(segments, x, y, reach):
    for k in range(segments.shape[0]):
        x0, y0, x1, y1 = segments[k, 0], segments[k, 1], segments[k, 2], segments[k, 3]
        if min(x0, x1) - reach <= x <= max(x0, x1) + reach and min(y0, y1) - reach <= y <= max(y0, y1) + reach:
            return True
    return False


def mark_swept(polygons, bodies, dt, in_pair, restitution, segments, asleep, fast):
    """Mark the step's swept polygons in fast (see the module); returns the bodies (n,) bool the
    wall rows leave out: asleep, and the swept (a copy of asleep then). Compiled code only."""
    raise NotImplementedError("mark_swept is called from compiled code")


def keep_starts(polygons, bodies, fast):
    """Keep the swept polygons' poses before the step moves them. Compiled code only."""
    raise NotImplementedError("keep_starts is called from compiled code")


def fly_swept(polygons, bodies, statics, dt, fast, log, now, frame_collisions):
    """Fly each swept polygon's step from its kept start against the walls (the module), in
    place, logging its wall impacts; returns the log. Compiled code only."""
    raise NotImplementedError("fly_swept is called from compiled code")


def outpaced(polygons, bodies, margin, dt, asleep):
    """Is there a pair with a polygon too fast for the step's contacts to follow (the module)?
    Compiled code only."""
    raise NotImplementedError("outpaced is called from compiled code")


def _none(polygons):
    return isinstance(polygons, types.NoneType)


@overload(mark_swept)
def _mark_swept(polygons, bodies, dt, in_pair, restitution, segments, asleep, fast):
    if _none(polygons):
        return lambda polygons, bodies, dt, in_pair, restitution, segments, asleep, fast: asleep

    def mark(polygons, bodies, dt, in_pair, restitution, segments, asleep, fast):
        b, count, left_out = bodies, 0, asleep
        if restitution > 0.0:
            for i in range(b.positions.shape[0]):
                # polygons only: the flight meets the walls at the vertices, and a capsule's
                # (its cap centres) lie its radius inside its outline; it keeps its wall rows
                if b.shapes[i] != POLYGON or asleep[i] or in_pair[i]:
                    continue
                reach = _reach(b, dt, i)
                if reach <= b.radii[i] or _near_a_segment(segments, b.positions[i, 0], b.positions[i, 1],
                                                          b.radii[i] + reach):
                    continue
                if count == 0:
                    left_out = asleep.copy()
                left_out[i] = True
                fast.swept[count] = i
                count += 1
        fast.count[0] = count
        return left_out
    return mark


@overload(keep_starts)
def _keep_starts(polygons, bodies, fast):
    if _none(polygons):
        return lambda polygons, bodies, fast: None

    def keep(polygons, bodies, fast):
        b = bodies
        for c in range(fast.count[0]):
            i, start = fast.swept[c], fast.start[c]
            start[0], start[1], start[2] = b.positions[i, 0], b.positions[i, 1], b.velocities[i, 0]
            start[3], start[4], start[5] = b.velocities[i, 1], b.angles[i], b.angular_velocities[i]
    return keep


@overload(fly_swept)
def _fly_swept(polygons, bodies, statics, dt, fast, log, now, frame_collisions):
    if _none(polygons):
        return lambda polygons, bodies, statics, dt, fast, log, now, frame_collisions: log

    def fly_all(polygons, bodies, statics, dt, fast, log, now, frame_collisions):
        s = statics
        for c in range(fast.count[0]):
            log = fly(bodies, fast.swept[c], fast.start[c], s.box, s.restitution, s.friction, s.rest_speed, s.keep,
                      dt, log, now, frame_collisions)
        return log
    return fly_all


@overload(outpaced)
def _outpaced(polygons, bodies, margin, dt, asleep):
    if _none(polygons):
        return lambda polygons, bodies, margin, dt, asleep: False
    return lambda polygons, bodies, margin, dt, asleep: pair_outpaced(bodies, margin, dt, asleep)


@kernel
def pair_outpaced(bodies, margin, dt, asleep):
    """outpaced: a body moving farther than its margin, against every other body."""
    b = bodies
    n = b.positions.shape[0]
    if n < 2:
        return False
    for i in range(n):
        if asleep[i] or _reach(b, dt, i) <= margin[i]:
            continue   # its margin covers its step
        for j in range(n):
            if j != i and not (b.shapes[i] == CIRCLE and b.shapes[j] == CIRCLE) and _pair_outpaced(b, margin, dt,
                                                                                                  i, j):
                return True
    return False


@inlined
def _pair_outpaced(b, margin, dt, i, j):
    """Do bodies i and j close more in the step than their margins cover, and do their bounding
    circles come within reach during it (relative motion in a straight line, the relative
    acceleration's ½·a·dt² as slack)?"""
    p, v, a, w, r = b.positions, b.velocities, b.accelerations, b.angular_velocities, b.radii
    dvx, dvy = v[j, 0] - v[i, 0], v[j, 1] - v[i, 1]
    slack = 0.5 * length(a[j, 0] - a[i, 0], a[j, 1] - a[i, 1]) * dt * dt
    closing = length(dvx, dvy) * dt + (abs(w[i]) * r[i] + abs(w[j]) * r[j]) * dt + 2.0 * slack
    if closing <= margin[i] + margin[j]:
        return False
    dx, dy = p[j, 0] - p[i, 0], p[j, 1] - p[i, 1]
    speed2 = dvx * dvx + dvy * dvy
    t = min(max(-(dx * dvx + dy * dvy) / speed2, 0.0), dt) if speed2 > 0.0 else 0.0
    cx, cy = dx + dvx * t, dy + dvy * t
    return cx * cx + cy * cy <= (r[i] + r[j] + slack) ** 2


@kernel
def _first_root(gap, rate, bend, longest):
    """The first time in (0, longest] at which gap + rate·t + bend·t² reaches 0 (gap >= 0), or
    longest; 0 where it is at 0 and going below."""
    if gap <= 0.0 and (rate < 0.0 or (rate == 0.0 and bend < 0.0)):
        return 0.0
    disc = rate * rate - 4.0 * bend * gap
    if disc < 0.0:
        return longest
    q = -0.5 * (rate + math.sqrt(disc)) if rate >= 0.0 else -0.5 * (rate - math.sqrt(disc))
    best = longest
    if bend != 0.0 and 0.0 < q / bend < best:
        best = q / bend
    if q != 0.0 and 0.0 < gap / q < best:
        best = gap / q
    return best


@kernel
def _vertex(corners, k, cos, sin):
    """Vertex k's arm from the centroid at the angle whose cos and sin are given."""
    return cos * corners[k, 0] - sin * corners[k, 1], sin * corners[k, 0] + cos * corners[k, 1]


@kernel
def _wall(box, wall):
    """(axis, the wall's coordinate, the sign of its inward normal) of a wall side."""
    axis = wall // 2
    return axis, box[axis + 2 * (wall % 2)], 1.0 if wall % 2 == 0 else -1.0


@kernel
def _advance(state, accel, t):
    """Free flight of state (x, y, vx, vy, θ, ω) for t, in place (integrate.py's step)."""
    half = 0.5 * t * t
    state[0] += state[2] * t + accel[0] * half
    state[1] += state[3] * t + accel[1] * half
    state[2] += accel[0] * t
    state[3] += accel[1] * t
    state[4] += state[5] * t


@kernel
def _earliest(state, accel, corners, box, longest, touch, slow):
    """(the next advance: the first root of every vertex's bound against every wall, the wall
    met (-1 if none: a vertex touching it and moving into it faster than `slow`), and the
    meeting point's arm x, y)."""
    cos, sin = math.cos(state[4]), math.sin(state[4])
    w = state[5]
    advance, touched, arm_x, arm_y, deepest = longest, -1, 0.0, 0.0, np.inf
    for wall in range(4):
        axis, bound, inward = _wall(box, wall)
        first, sum_x, sum_y, touching, fastest = -1, 0.0, 0.0, 0, 0.0
        for k in range(corners.shape[0]):
            rx, ry = _vertex(corners, k, cos, sin)
            gap = inward * (state[axis] + (rx if axis == 0 else ry) - bound)
            rate = inward * (state[2 + axis] + (-w * ry if axis == 0 else w * rx))
            if gap <= touch:
                touching += 1
                sum_x, sum_y = sum_x + rx, sum_y + ry
                if rate < -slow and rate < fastest:
                    first, fastest = k, rate
                    continue
            bend = 0.5 * (inward * accel[axis] - w * w * math.hypot(rx, ry))
            advance = min(advance, _first_root(max(gap, 0.0), rate, bend, longest))
        if first >= 0 and fastest < deepest:   # a touching vertex moving into the wall: an impact
            deepest, touched = fastest, wall
            arm_x, arm_y = _vertex(corners, first, cos, sin)
            mid_x, mid_y = sum_x / touching, sum_y / touching
            if _point_rate(state, mid_x, mid_y, axis, inward) < 0.0:
                arm_x, arm_y = mid_x, mid_y   # a face flat on the wall: pushed at its middle
    return advance, touched, arm_x, arm_y


@kernel
def _point_rate(state, arm_x, arm_y, axis, inward):
    """The speed of the body's point at arm along a wall's inward normal."""
    return inward * (state[2 + axis] + (-state[5] * arm_y if axis == 0 else state[5] * arm_x))


@kernel
def _impact(state, mass, inertia, arm_x, arm_y, axis, inward, restitution, friction):
    """Newton's impulse with restitution, and Coulomb friction, at the point at arm on a wall;
    in place. Returns the normal impulse."""
    nx, ny = (inward, 0.0) if axis == 0 else (0.0, inward)
    closing = _point_rate(state, arm_x, arm_y, axis, inward)
    turn_n = arm_x * ny - arm_y * nx
    impulse = -(1.0 + restitution) * closing / (1.0 / mass + turn_n * turn_n / inertia)
    _kick(state, mass, inertia, nx, ny, turn_n, impulse)
    if friction > 0.0:
        tx, ty = -ny, nx
        sliding = state[2] * tx + state[3] * ty + state[5] * (arm_x * ty - arm_y * tx)
        turn_t = arm_x * ty - arm_y * tx
        along = -sliding / (1.0 / mass + turn_t * turn_t / inertia)
        bound = friction * impulse
        _kick(state, mass, inertia, tx, ty, turn_t, min(max(along, -bound), bound))
    return impulse


@kernel
def _kick(state, mass, inertia, dx, dy, turn, impulse):
    state[2] += impulse * dx / mass
    state[3] += impulse * dy / mass
    state[5] += impulse * turn / inertia


@kernel
def _put_back(state, corners, box):
    """Every vertex back inside the walls, and the velocity into a wall touched removed; in place."""
    cos, sin = math.cos(state[4]), math.sin(state[4])
    for wall in range(4):
        axis, bound, inward = _wall(box, wall)
        gap = np.inf
        for k in range(corners.shape[0]):
            rx, ry = _vertex(corners, k, cos, sin)
            gap = min(gap, inward * (state[axis] + (rx if axis == 0 else ry) - bound))
        if gap < 0.0:
            state[axis] -= inward * gap
            if inward * state[2 + axis] < 0.0:
                state[2 + axis] = 0.0


@compiled(error_model="numpy")
def fly(bodies, i, start, box, restitution, friction, rest_speed, keep, dt, log, now, frame_collisions):
    """Body i's step of dt from start (x, y, vx, vy, θ, ω; kept before the step moved it, and
    used up) against the walls, in place: see the module. A vertex meeting a wall slower than
    rest_speed (or a billionth of its size a step) rests there. Returns the log."""
    b = bodies
    state = start
    state[2], state[3], state[5] = keep * state[2], keep * state[3], keep * state[5]   # damping, as integrate
    accel = b.accelerations[i]
    corners = b.body_vertices[b.vertex_start[i]:b.vertex_start[i + 1]]
    touch = TOUCH * b.radii[i] + 1e-14 * (1.0 + max(abs(box[0]), abs(box[1]), abs(box[2]), abs(box[3])))
    slow = max(rest_speed, TOUCH * b.radii[i] / dt)
    left = dt
    for _ in range(MAX_ADVANCES):
        if left <= 0.0:
            break
        advance, wall, arm_x, arm_y = _earliest(state, accel, corners, box, left, touch, slow)
        if wall >= 0:
            axis, bound, inward = _wall(box, wall)
            impulse = _impact(state, b.masses[i], b.inertias[i], arm_x, arm_y, axis, inward, restitution, friction)
            log = with_room(log, 1)
            x, y = state[0] + arm_x, state[1] + arm_y
            append(log, now, WALL, i, wall, impulse, x, y)
            frame_collisions[WALL] += 1
            continue
        if advance < STALL * dt:
            break   # resting on a wall, or a touch it cannot follow: the rest of the step flown freely
        _advance(state, accel, advance)
        left -= advance
    if left > 0.0:
        _advance(state, accel, left)
        _put_back(state, corners, box)
    b.positions[i, 0], b.positions[i, 1], b.velocities[i, 0], b.velocities[i, 1] = state[0], state[1], state[2], \
        state[3]
    b.angles[i], b.angular_velocities[i] = state[4], state[5]
    return log


def segment_reach(polygons, bodies, dt, margin, segments, out):
    """How far each body's rows with the segments reach (n,): a polygon's whole step's travel
    when that is more than its margin (as a wall's rows reach: rows.wall_manifolds), so that no
    speed carries it past a segment; a circle's margin (the segment bounce takes its impacts).
    margin itself for a world without polygons or segments. Compiled code only."""
    raise NotImplementedError("segment_reach is called from compiled code")


@overload(segment_reach)
def _segment_reach(polygons, bodies, dt, margin, segments, out):
    if _none(polygons):
        return lambda polygons, bodies, dt, margin, segments, out: margin

    def reach(polygons, bodies, dt, margin, segments, out):
        if segments.shape[0] == 0:
            return margin
        b = bodies
        for i in range(margin.shape[0]):
            out[i] = margin[i] if b.shapes[i] == CIRCLE else max(margin[i], _reach(b, dt, i))
        return out
    return reach


@kernel
def note_outpaced(counts, frame):
    """Count a step outpaced (Fast.outpaced), keeping the frame of the first."""
    if counts[0] == 0:
        counts[1] = frame
    counts[0] += 1
