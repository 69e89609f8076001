"""Held from below: shock propagation for a stack the contact solver cannot carry.

Sweeps of sequential impulses (solver.py) pass a weight down a stack at a rate set by the mass
ratio: a body a thousand times heavier than the ball it rests on needs thousands of sweeps, and
in twenty the heavy body sinks through the ball, step after step, until the two lie on top of
each other (silently, before this module).

So a pass that ends with rows still closing faster than half a step of their bodies' pull
(velocities), or with less than half of an overlap's share taken out (positions), while a pair
of the step has an upper body HOLD_RATIO times heavier than its lower one, holds every row left
short once more, from the ground up, lowest point first, each with its lower body taken as fixed:
only the upper body moves, so no row undoes the one below it (shock propagation, Guendelman,
Bridson and Fedkiw 2003). The heavy pair need not be among the late rows: in a column of light
balls under a heavy one, the sweeps end with the heavy ball's own row met and every row below
it late.

That does not keep momentum, so the step reports it and its frame is flagged approximate. A pass
that converged holds nothing; nor does one that merely stopped short in a pile of like masses
(the polygons scene's pile leaves rows closing at 0.10-0.14 units/s after its sweeps, masses
within 1.4 of each other), which the next step's sweeps take up as before.
"""
import numpy as np

from ..core.arrays import stable_order_of_floats
from ..core.compiling import compiled, inlined, kernel
from .contact_row import inverses, kicked, load, relative, store

HOLD_RATIO = 10.0   # an upper body this many times heavier than the lower one: the sweeps cannot carry it


@kernel
def pull(accelerations, i, j):
    """The larger acceleration of a row's bodies (a wall's is 0)."""
    largest = (accelerations[i, 0] ** 2 + accelerations[i, 1] ** 2) ** 0.5
    if j >= 0:
        largest = max(largest, (accelerations[j, 0] ** 2 + accelerations[j, 1] ** 2) ** 0.5)
    return largest


@inlined
def _height(rows, r, accelerations):
    """How high row r's point is against its bodies' pull (their summed accelerations): lower points
    sort first. 0 where nothing pulls."""
    i, j = rows.i[r], rows.j[r]
    down_x, down_y = accelerations[i, 0], accelerations[i, 1]
    if j >= 0:
        down_x, down_y = down_x + accelerations[j, 0], down_y + accelerations[j, 1]
    return -(rows.point[r, 0] * down_x + rows.point[r, 1] * down_y)


@inlined
def _below_is_j(rows, r, accelerations):
    """Does body j of pair row r lie below body i, along the bodies' summed pull?"""
    i, j = rows.i[r], rows.j[r]
    down_x = accelerations[i, 0] + accelerations[j, 0]
    down_y = accelerations[i, 1] + accelerations[j, 1]
    return rows.normal[r, 0] * down_x + rows.normal[r, 1] * down_y > 0.0


@compiled
def hold_from_below(rows, rows_of, target, base, per_pull, per_target, accelerations, inverse_masses,
                    inverse_inertias, lin, ang, share, accumulated, base_t, friction):
    """After a pass's sweeps: if one of the rows rows_of[k] is a pair whose upper body is
    HOLD_RATIO times heavier than its lower one, and a row still closes faster than target[k] less
    its slack, per_pull times its bodies' pull plus per_target times target[k] (a closing is
    base[k] plus what lin (n, 2), ang (n,) add), hold every row short of its
    target once more, lowest point first, moving only its upper body (the one its bodies' pull
    points away from; a wall holds its body as a sweep does): the upper body alone takes the
    impulse that brings the row to its target, and an impulse moves lin by `share` of it. A row
    that parts faster than its target while it pushes (accumulated (k,) its pass's impulses) gives
    back what parts it, down to no push at all: the sweeps, short of converging, leave the light
    bodies under a heavy one bouncing (a column of light balls under a heavy one rose and fell
    and sank into itself), and held only where they closed,
    each body was lifted after the one below it. Nothing happens where nothing pulls. Returns the
    number of rows held (0: nothing was held).

    With friction (base_t (k,) the rows' tangential speeds before any impulse, as base is along
    the normal), each held row also stops its upper body sliding on the lower one, within
    friction times the row's push (its pass's and the hold's): held along the normal alone, a box
    a thousand times heavier than the box under it walked sideways off it, its
    friction left to the sweeps, which cannot carry that ratio either.

    The held impulses are not added to the rows' accumulated ones: those are what the next step's
    sweeps start from (warmstart.py), and these, which push the upper body with no reaction on the
    lower, solve no contact. Kept apart, the sweeps go on carrying the weight down from step to
    step. (Added in, a heavy ball on a column of five at 1000:1 overlapped 0.15 radii and was still
    moving at 0.7 units/s after 3 s; kept apart, 0.06 radii and 0.3 units/s.)"""
    I, J, N, L = rows.i, rows.j, rows.normal, rows.lever
    heavy_on_light = False   # looked for first: most steps have none, and cost no more than this
    for k in range(rows_of.shape[0]):
        r = rows_of[k]
        if J[r] >= 0:
            upper, lower = (I[r], J[r]) if _below_is_j(rows, r, accelerations) else (J[r], I[r])
            if inverse_masses[lower] >= HOLD_RATIO * inverse_masses[upper]:
                heavy_on_light = True
                break
    if not heavy_on_light:
        return 0
    # the rows with a pull: each is held in turn, as the rows under it leave it (one that meets its
    # target now may not once the body under it has been held)
    short = np.empty(rows_of.shape[0], np.int64)
    count, late = 0, False
    for k in range(rows_of.shape[0]):
        r = rows_of[k]
        i, j = I[r], J[r]
        strength = pull(accelerations, i, j)
        if strength > 0.0:
            short[count] = k
            count += 1
            closing = base[k] + relative(load(lin, ang, i, j), j, N[r, 0], N[r, 1], L[r, 0], L[r, 2])
            off = target[k] - closing if closing < target[k] or accumulated[r] > 0.0 else 0.0
            late = late or abs(off) > per_pull * strength + abs(per_target * target[k])
    if not late:
        return 0
    heights = np.empty(count)
    for c in range(count):
        heights[c] = _height(rows, rows_of[short[c]], accelerations)
    for c in stable_order_of_floats(heights):   # stable: the same bytes on every run
        k = short[c]
        r = rows_of[k]
        i, j, nx, ny = I[r], J[r], N[r, 0], N[r, 1]
        m = inverses(inverse_masses, inverse_inertias, i, j)
        if j >= 0:   # the lower body, along the pull, is held fixed: only the upper one moves
            m = (m[0], m[1], 0.0, 0.0) if _below_is_j(rows, r, accelerations) else (0.0, 0.0, m[2], m[3])
        v = load(lin, ang, i, j)
        closing = base[k] + relative(v, j, nx, ny, L[r, 0], L[r, 2])
        # the closing speed a unit impulse adds, on the bodies that move
        per_impulse = share * (m[0] + m[1] * L[r, 0] * L[r, 0] + m[2] + m[3] * L[r, 2] * L[r, 2])
        impulse = max((target[k] - closing) / per_impulse, -accumulated[r])   # a row never pulls
        if impulse != 0.0:   # else held by a row below it, or parting with nothing to give back
            v = kicked(v, m, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3], share * impulse, 0.0)
        push = accumulated[r] + impulse
        if friction > 0.0 and push > 0.0:
            sliding = base_t[k] + relative(v, j, -ny, nx, L[r, 1], L[r, 3])
            per_slide = share * (m[0] + m[1] * L[r, 1] * L[r, 1] + m[2] + m[3] * L[r, 3] * L[r, 3])
            grip = friction * push
            v = kicked(v, m, j, nx, ny, L[r, 0], L[r, 1], L[r, 2], L[r, 3], 0.0,
                       share * min(max(-sliding / per_slide, -grip), grip))
        store(lin, ang, i, j, v)
    return count


def held_note(frame: int) -> str:
    """What a run says (once) when its first held frame is `frame`."""
    return (f"the contact solver could not carry a weight down a stack in its sweeps (a body much heavier "
            f"than those under it), first at frame {frame}; it held those bodies from below, which does not "
            f"keep momentum")
