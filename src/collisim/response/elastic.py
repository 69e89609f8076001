"""Two-body collision response from conservation of momentum and kinetic energy.

For circles the impulse acts along the line of centres n = (p_j - p_i)/|p_j - p_i|. With the
normal approach speed u = (v_j - v_i)·n < 0 and restitution e, the impulse

    J = -(1 + e) · u / (1/m_i + 1/m_j)

gives v_i -= J/m_i · n and v_j += J/m_j · n. For e = 1 this is the video's 2D elastic formula
v_1' = v_1 - 2 m_2/(m_1+m_2) · <v_1 - v_2, x_1 - x_2>/|x_1 - x_2|² · (x_1 - x_2), with both
new velocities computed from the pre-collision ones.

Contacts are resolved one after another in their given (sorted) order, so the same input
always gives the same bytes. Only approaching pairs get an impulse: a pair that overlaps but
already separates is left alone.

Overlap is then removed by moving the two centres apart along n, split by inverse mass
(the heavier one moves less). This changes no velocity, so it leaves kinetic energy and
momentum exactly as they are; under gravity it changes potential energy by m·g·Δy, which
shows as energy drift of the discrete method.
"""
import math

from numba import njit


@njit(cache=True)
def resolve_contacts(positions, velocities, masses, radii, contacts, restitution,
                     event_impulse, event_point):
    """Apply impulses and separate overlaps in place, contact by contact.

    positions, velocities: (n, 2); masses, radii: (n,); contacts: (k, 2) intp with i < j
    event_impulse: (k,) out, 0 for a contact that was not approaching; event_point: (k, 2) out
    Returns the number of collisions (approaching contacts).
    """
    collisions = 0
    for c in range(contacts.shape[0]):
        i, j = contacts[c, 0], contacts[c, 1]
        nx, ny, distance = _line_of_centres(positions, i, j)
        inv_i, inv_j = 1.0 / masses[i], 1.0 / masses[j]
        approach = (velocities[j, 0] - velocities[i, 0]) * nx + (velocities[j, 1] - velocities[i, 1]) * ny
        event_impulse[c] = 0.0
        if approach < 0.0:
            impulse = -(1.0 + restitution) * approach / (inv_i + inv_j)
            velocities[i, 0] -= impulse * inv_i * nx
            velocities[i, 1] -= impulse * inv_i * ny
            velocities[j, 0] += impulse * inv_j * nx
            velocities[j, 1] += impulse * inv_j * ny
            event_impulse[c] = impulse
            collisions += 1
        event_point[c, 0] = positions[i, 0] + nx * radii[i]
        event_point[c, 1] = positions[i, 1] + ny * radii[i]
        _push_apart(positions, masses, i, j, nx, ny, radii[i] + radii[j] - distance)
    return collisions


@njit(cache=True)
def _line_of_centres(positions, i, j):
    """(nx, ny, distance): the unit normal from i to j and the distance between the centres.
    Coincident centres have no line of centres: x is picked, deterministically."""
    nx = positions[j, 0] - positions[i, 0]
    ny = positions[j, 1] - positions[i, 1]
    distance = math.sqrt(nx * nx + ny * ny)
    if distance == 0.0:
        return 1.0, 0.0, 0.0
    return nx / distance, ny / distance, distance


@njit(cache=True)
def _push_apart(positions, masses, i, j, nx, ny, overlap):
    """Move i and j apart along the unit normal (nx, ny) by `overlap`, split by inverse mass."""
    if overlap <= 0.0:
        return
    inv_i, inv_j = 1.0 / masses[i], 1.0 / masses[j]
    share_i = inv_i / (inv_i + inv_j)
    positions[i, 0] -= overlap * share_i * nx
    positions[i, 1] -= overlap * share_i * ny
    positions[j, 0] += overlap * (1.0 - share_i) * nx
    positions[j, 1] += overlap * (1.0 - share_i) * ny


@njit(cache=True)
def separate_contacts(positions, masses, radii, contacts):
    """Remove overlaps left among this step's contacts (k, 2), positions only, in order.

    A wall bounce after the response can push a particle back into the partner it was just
    separated from; this second pass takes it out again. No velocity changes.
    """
    for c in range(contacts.shape[0]):
        i, j = contacts[c, 0], contacts[c, 1]
        nx, ny, distance = _line_of_centres(positions, i, j)
        if distance > 0.0:
            _push_apart(positions, masses, i, j, nx, ny, radii[i] + radii[j] - distance)
