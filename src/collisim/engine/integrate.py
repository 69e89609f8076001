"""Particle dynamics, the video's update(dt): constant acceleration makes the step exact.

    v ← k·v, ω ← k·ω   damping: k = d**dt keeps the fraction d of a velocity over a second
                       (World.damping, pymunk's Space.damping); k = 1 without damping
    p += v·dt + ½·a·dt²
    v += a·dt
    θ += ω·dt          (no torque acts between contacts)
"""
from ..core.compiling import kernel


@kernel
def integrate(positions, velocities, accelerations, angles, angular_velocities, dt, keep):
    """Advance every body by dt in place, keeping the fraction `keep` of its velocities first.

    positions, velocities, accelerations: (n, 2); angles, angular_velocities: (n,)
    """
    half_dt2 = 0.5 * dt * dt
    for i in range(positions.shape[0]):
        if keep != 1.0:
            velocities[i, 0] *= keep
            velocities[i, 1] *= keep
            angular_velocities[i] *= keep
        for axis in range(2):
            positions[i, axis] += velocities[i, axis] * dt + accelerations[i, axis] * half_dt2
            velocities[i, axis] += accelerations[i, axis] * dt
        angles[i] += angular_velocities[i] * dt
