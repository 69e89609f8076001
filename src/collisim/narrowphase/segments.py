"""Thin barriers for the discrete engine: detection and response at one instant.

A segment (x0, y0, x1, y1) has no thickness, collides on both sides, and its end
points act as round caps. Discrete detection, as for the box walls: take the point
of the segment closest to the centre; the circle touches the segment if that point
is within its radius. The contact normal n goes from the closest point to the
centre (at an end point this is what makes the cap round).

Response, only if the particle is moving towards the segment (v·n < 0): reflect
the normal velocity with restitution, v_n -> -e v_n, and push the particle out
along n to exactly its radius. A particle that is still overlapping but already
moving away is left alone.

This is a check at frame (or substep) times only: a particle that moves more than
its diameter in one step can jump over the segment without ever overlapping it at
a checked time ("tunnelling"). Method `ccd` (collisim.ccd) does not have that flaw.
"""
import numpy as np
from numba import njit

from ..ccd.geometry import closest_on_segment, contact_normal


@njit(cache=True)
def _bounce(positions, velocities, radii, masses, i, segment, restitution):
    """Detect and resolve particle i against one segment (4,). Returns (impulse, contact x,
    contact y); impulse 0 means no collision."""
    x0, y0, x1, y1 = segment
    px, py = positions[i, 0], positions[i, 1]
    qx, qy, _ = closest_on_segment(px, py, x0, y0, x1, y1)
    nx, ny, distance = contact_normal(px, py, qx, qy, x0, y0, x1, y1)
    vn = velocities[i, 0] * nx + velocities[i, 1] * ny
    if distance == 0.0 and vn > 0.0:  # centre on the segment: the normal faces the incoming side
        nx, ny, vn = -nx, -ny, -vn
    if distance > radii[i] or vn >= 0.0:
        return 0.0, qx, qy
    velocities[i, 0] -= (1.0 + restitution) * vn * nx
    velocities[i, 1] -= (1.0 + restitution) * vn * ny
    positions[i, 0], positions[i, 1] = qx + radii[i] * nx, qy + radii[i] * ny
    return masses[i] * (1.0 + restitution) * -vn, qx, qy


@njit(cache=True)
def collide_segments(positions, velocities, radii, masses, segments, restitution):
    """Collide every particle with every segment, in place.

    positions, velocities (n, 2) are updated; radii, masses (n,); segments (m, 4) rows
    (x0, y0, x1, y1); restitution e in [0, 1]. Particles are treated in index order,
    and each one against the segments in index order.

    Returns the k collisions of this call as (particle (k,) int64, segment (k,) int64,
    impulse (k,) float64 = m |Δv_n|, point (k, 2) contact points).
    """
    n, m = positions.shape[0], segments.shape[0]
    capacity = max(n, 16)
    particle, segment = np.empty(capacity, np.int64), np.empty(capacity, np.int64)
    impulse, point = np.empty(capacity), np.empty((capacity, 2))
    count = 0
    for i in range(n):
        for s in range(m):
            delivered, x, y = _bounce(positions, velocities, radii, masses, i, segments[s], restitution)
            if delivered == 0.0:
                continue
            if count == capacity:
                capacity *= 2
                particle, segment = _grown(particle, capacity), _grown(segment, capacity)
                impulse, point = _grown(impulse, capacity), _grown(point, capacity)
            particle[count], segment[count], impulse[count] = i, s, delivered
            point[count, 0], point[count, 1] = x, y
            count += 1
    return particle[:count], segment[:count], impulse[:count], point[:count]


@njit(cache=True)
def _grown(array, capacity):
    """A copy of array with its first axis enlarged to capacity."""
    out = np.empty((capacity,) + array.shape[1:], array.dtype)
    out[:array.shape[0]] = array
    return out

