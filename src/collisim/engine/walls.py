"""Discrete collisions with the box walls, as the video describes them, done right.

Detection compares the particle's extreme point with the edge: the left wall is hit when
x - r <= xmin. A wall has infinite mass, so the response flips the normal velocity
component (scaled by the restitution e). Three details make it robust:

* respond only while moving toward the wall; a particle that is already leaving is never
  flipped back, so it cannot stick or jitter at the edge;
* the distance travelled beyond the wall is reflected back inside (scaled by e), which is
  where the particle would be had it bounced at the right moment; a very fast particle may
  cross the box several times in one step, and the loop reflects it until it is inside, so no
  speed can carry it out;
* under a constant acceleration the speed is made consistent with the reflected position
  (v² = v_c² - 2·g·h, with v_c the speed at the contact plane), so a bounce neither creates
  nor destroys energy: an elastic ball keeps its apex.
"""
import math

from numba import njit


@njit(cache=True)
def _bounce(overshoot, speed_in, pull, restitution):
    """Reflect a particle that went `overshoot` past the contact plane moving at `speed_in`
    (> 0, toward the wall) while accelerated toward the wall by `pull`.

    Returns (distance back inside, speed away from the wall, impulse per unit mass).
    """
    contact_speed = math.sqrt(max(speed_in * speed_in - 2.0 * pull * overshoot, 0.0))
    rebound = restitution * contact_speed
    inside = restitution * overshoot
    if pull > 0.0 and rebound * rebound < 2.0 * pull * inside:
        inside = rebound * rebound / (2.0 * pull)  # it cannot climb that far: stop at the apex
    speed_out = math.sqrt(max(rebound * rebound - 2.0 * pull * inside, 0.0))
    return inside, speed_out, contact_speed + rebound


@njit(cache=True)
def collide_walls(positions, velocities, accelerations, radii, masses, box, restitution,
                  event_particle, event_wall, event_impulse, event_point):
    """Resolve wall contacts in place; write one event per (particle, wall) hit.

    positions, velocities, accelerations: (n, 2); radii, masses: (n,); box: (4,) xmin, ymin, xmax, ymax
    event_*: outputs with room for 4·n events (event_point: (4n, 2))
    Returns (events written, wall hits). Several bounces off one wall in one step are one
    event carrying their summed impulse.
    """
    events = 0
    hits = 0
    for i in range(positions.shape[0]):
        for axis in range(2):
            low = box[axis] + radii[i]
            high = box[axis + 2] - radii[i]
            x = positions[i, axis]
            if low <= x <= high:
                continue
            v = velocities[i, axis]
            a = accelerations[i, axis]
            bounces_low, bounces_high, impulse_low, impulse_high = 0, 0, 0.0, 0.0
            if high <= low:  # the particle exactly fits: it can only sit in the middle
                x, v = 0.5 * (low + high), 0.0
            while x < low or x > high:
                if x < low and v < 0.0:
                    inside, speed, dv = _bounce(low - x, -v, -a, restitution)
                    x, v = low + inside, speed
                    impulse_low += masses[i] * dv
                    bounces_low += 1
                elif x > high and v > 0.0:
                    inside, speed, dv = _bounce(x - high, v, a, restitution)
                    x, v = high - inside, -speed
                    impulse_high += masses[i] * dv
                    bounces_high += 1
                else:  # beyond the wall but already leaving it: put it back on the wall
                    x = min(max(x, low), high)
            positions[i, axis] = x
            velocities[i, axis] = v
            for side in range(2):
                bounces = bounces_low if side == 0 else bounces_high
                if bounces > 0:
                    event_particle[events] = i
                    event_wall[events] = 2 * axis + side
                    event_impulse[events] = impulse_low if side == 0 else impulse_high
                    event_point[events, axis] = box[axis + 2 * side]
                    event_point[events, 1 - axis] = positions[i, 1 - axis]
                    events += 1
                    hits += bounces
    return events, hits


@njit(cache=True)
def clamp_into_box(positions, radii, box):
    """Put every circle back inside the box, positions only (after overlap removal may have
    pushed one a little past a wall). positions: (n, 2); radii: (n,)."""
    for i in range(positions.shape[0]):
        for axis in range(2):
            low, high = box[axis] + radii[i], box[axis + 2] - radii[i]
            positions[i, axis] = min(max(positions[i, axis], low), high)
