"""Particle dynamics, the video's update(dt): constant acceleration makes the step exact.

    p += v·dt + ½·a·dt²
    v += a·dt
"""
from numba import njit


@njit(cache=True)
def integrate(positions, velocities, accelerations, dt):
    """Advance every particle by dt in place.

    positions, velocities, accelerations: (n, 2)
    """
    half_dt2 = 0.5 * dt * dt
    for i in range(positions.shape[0]):
        for axis in range(2):
            positions[i, axis] += velocities[i, axis] * dt + accelerations[i, axis] * half_dt2
            velocities[i, axis] += accelerations[i, axis] * dt
