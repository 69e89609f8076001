"""Response for contacts between bodies, one contact after another in sorted (i, j) order, so
the same input always gives the same bytes.

Each contact's geometry is taken afresh from the narrow phase's contact function when its turn
comes, since the contacts before it may have moved its bodies (a cluster of three).
"""
from numba import njit

from ..narrowphase.registry import contact
from .impulse import apply_normal_impulse, push_apart


@njit(cache=True, error_model="numpy")
def resolve_pairs(shapes, positions, velocities, masses, radii, contacts, count, restitution,
                  out_impulse, out_point):
    """Impulse, then push-apart, for contacts[:count] (k, 2) with i < j, in place.

    out_impulse: (>= count,) the impulse of each contact, 0 for one that was not approaching;
    out_point: (>= count, 2) its contact point. Returns the number of collisions (contacts
    that got an impulse).
    """
    collisions = 0
    for c in range(count):
        i, j = contacts[c, 0], contacts[c, 1]
        nx, ny, depth, px, py = contact(shapes, positions, radii, i, j)
        out_impulse[c] = apply_normal_impulse(velocities, masses, i, j, nx, ny, restitution)
        if out_impulse[c] > 0.0:
            collisions += 1
        out_point[c, 0], out_point[c, 1] = px, py
        push_apart(positions, masses, i, j, nx, ny, depth)
    return collisions


@njit(cache=True, error_model="numpy")
def separate_pairs(shapes, positions, masses, radii, contacts, count):
    """Push apart what is left of the overlaps of contacts[:count], positions only, in order.

    A wall bounce after the response can push a body back into the partner it was just
    separated from; this pass takes it out again. No velocity changes. Coincident centres
    have no normal to push along and are left to the next step's response.
    """
    for c in range(count):
        i, j = contacts[c, 0], contacts[c, 1]
        if positions[i, 0] != positions[j, 0] or positions[i, 1] != positions[j, 1]:
            nx, ny, depth, _, _ = contact(shapes, positions, radii, i, j)
            push_apart(positions, masses, i, j, nx, ny, depth)
