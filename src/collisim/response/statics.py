"""Bouncing off the static geometry: the box walls and thin segments.

Walls, as the video describes them, done right. A wall has infinite mass, so the response
flips the normal velocity component (scaled by the restitution e). Three details make it
robust:

* respond only while moving toward the wall; a body that is already leaving is never
  flipped back, so it cannot stick or jitter at the edge;
* the distance travelled beyond the wall is reflected back inside (scaled by e), which is
  where the body would be had it bounced at the right moment; a very fast body may cross the
  box several times in one step, and the loop reflects it until it is inside, so no speed can
  carry it out;
* under a constant acceleration the speed is made consistent with the reflected position
  (v² = v_c² - 2·g·h, with v_c the speed at the contact plane), so a bounce neither creates
  nor destroys energy: an elastic ball keeps its apex.

Segments: only if the body moves towards the segment (v·n < 0), it is reflected along the
segment's normal n as off a wall: the normal speed at the contact is reflected with restitution
and the distance past the contact reflected back out, energy-consistently. A body the contact
solver held against a segment this step (resting there, or in a pile: response/rows.py) is only
put back on it. This is a check at step times only: a body that moves more than its
diameter in one step can jump over a segment (tunnelling); method `ccd` cannot.
"""
import math

from ..core.compiling import kernel

from ..core.geometry.box import centre_range
from ..narrowphase.statics import circle_segment

FOLD_AFTER = 64        # reflections in one step before an elastic free flight is folded in O(1)
MAX_BOUNCES = 10_000   # reflections in one step beyond which the speed is an error (see above)
# Box crossings in one step beyond which even an elastic free flight is an error: a fold lands
# within about crossings x 1e-16 of the box's size of where exact arithmetic would (rounding in
# the distance flown), so up to here to 1e-4 of the box; beyond it, the crossings could not even
# be counted exactly (2^53), and the body's place in the box would be noise.
MAX_CROSSINGS = 1e12


@kernel
def _reflect(overshoot, speed_in, pull, restitution):
    """Reflect a body that went `overshoot` past the contact plane moving at `speed_in`
    (> 0, toward the wall) while accelerated toward the wall by `pull`.

    Returns (distance back inside, speed away from the wall, speed change)."""
    contact_speed = math.sqrt(max(speed_in * speed_in - 2.0 * pull * overshoot, 0.0))
    rebound = restitution * contact_speed
    inside = restitution * overshoot
    if pull > 0.0 and rebound * rebound < 2.0 * pull * inside:
        inside = rebound * rebound / (2.0 * pull)  # it cannot climb that far: stop at the apex
    speed_out = math.sqrt(max(rebound * rebound - 2.0 * pull * inside, 0.0))
    return inside, speed_out, contact_speed + rebound


@kernel
def _fold(x, v, low, high):
    """Free elastic flight between two walls, x past one of them, in O(1) however far: the
    reflections unfold into a straight line of period 2·(high - low). Returns (x, v, bounces
    off low, bounces off high)."""
    span = high - low
    over = x - high if x > high else low - x        # beyond the wall it is heading for
    k = 1 + int(math.floor(over / span))            # reflections needed
    rest = over - (k - 1) * span                     # in (0, span]: distance back inside after the last
    first_high = x > high
    toward_high_after = (k % 2 == 0) == first_high  # an even count ends moving as it started
    x = (low + rest) if toward_high_after else (high - rest)
    v = abs(v) if toward_high_after else -abs(v)
    half, odd = k // 2, k % 2
    return (x, v, half + (odd if not first_high else 0), half + (odd if first_high else 0))


@kernel
def bounce_between_walls(positions, velocities, accelerations, radii, masses, box, restitution, i, axis):
    """Bring body i, whose centre is past a wall on `axis`, back inside, in place.

    Returns (bounces off the low wall, off the high wall, impulse on each): several bounces
    off one wall in one step carry their summed impulse. The work is bounded whatever the
    speed: an elastic body in free flight that would bounce more than FOLD_AFTER times is
    folded back in one step (_fold), up to MAX_CROSSINGS crossings of the box; any other past
    MAX_BOUNCES, or one past MAX_CROSSINGS, is a speed this frame rate cannot represent, and one
    clear error."""
    low, high = centre_range(box, axis, radii[i])
    x, v, a = positions[i, axis], velocities[i, axis], accelerations[i, axis]
    bounces_low, bounces_high, impulse_low, impulse_high = 0, 0, 0.0, 0.0
    if high <= low:  # the body exactly fits: it can only sit in the middle
        x, v = 0.5 * (low + high), 0.0
    while x < low or x > high:
        if bounces_low + bounces_high >= FOLD_AFTER and restitution == 1.0 and a == 0.0:
            if max(x - high, low - x) > MAX_CROSSINGS * (high - low):
                raise ValueError("a body would cross the box more than 1e12 times in one step: its speed "
                                 "cannot be represented at this frame rate; use more substeps or a lower speed")
            speed = abs(v)
            x, v, more_low, more_high = _fold(x, v, low, high)
            impulse_low += 2.0 * masses[i] * speed * more_low
            impulse_high += 2.0 * masses[i] * speed * more_high
            bounces_low, bounces_high = bounces_low + more_low, bounces_high + more_high
            break
        if bounces_low + bounces_high >= MAX_BOUNCES:
            raise ValueError("a body would cross the box more than 10 000 times in one step: its speed "
                             "cannot be represented at this frame rate; use more substeps or a lower speed")
        if x < low and v < 0.0:
            inside, speed, dv = _reflect(low - x, -v, -a, restitution)
            x, v = low + inside, speed
            impulse_low += masses[i] * dv
            bounces_low += 1
        elif x > high and v > 0.0:
            inside, speed, dv = _reflect(x - high, v, a, restitution)
            x, v = high - inside, -speed
            impulse_high += masses[i] * dv
            bounces_high += 1
        else:  # beyond the wall but already leaving it: put it back on the wall
            x = min(max(x, low), high)
    positions[i, axis] = x
    velocities[i, axis] = v
    return bounces_low, bounces_high, impulse_low, impulse_high


@kernel
def bounce_off_segment(positions, velocities, accelerations, radii, masses, segments, i, s, restitution):
    """Respond to body i touching segment s, in place, as a wall does (_reflect): the normal
    velocity reflected with restitution at the speed the body had where it met the segment, the
    distance it went past the contact reflected back out with it, and the speed made consistent
    with that place under its acceleration (reflecting the step's end velocity instead, which
    had fallen up to a step's travel past the contact, sent a ball dropped at e = 0.8 back 1.8 %
    too fast). Returns (impulse, contact x, contact y); impulse 0 means it was not approaching."""
    nx, ny, depth, qx, qy = circle_segment(positions, radii, i, segments, s)
    vn = velocities[i, 0] * nx + velocities[i, 1] * ny
    if positions[i, 0] == qx and positions[i, 1] == qy and vn > 0.0:
        nx, ny, vn = -nx, -ny, -vn  # centre on the segment: the normal faces the incoming side
    if vn >= 0.0:
        return 0.0, qx, qy
    pull = -(accelerations[i, 0] * nx + accelerations[i, 1] * ny)   # toward the segment
    inside, speed_out, dv = _reflect(max(depth, 0.0), -vn, pull, restitution)
    velocities[i, 0] += (speed_out - vn) * nx
    velocities[i, 1] += (speed_out - vn) * ny
    positions[i, 0], positions[i, 1] = qx + (radii[i] + inside) * nx, qy + (radii[i] + inside) * ny
    return masses[i] * dv, qx, qy


@kernel
def _place_on_segment(positions, radii, i, nx, ny, qx, qy):
    """Put body i at exactly its radius from the segment's closest point q, along n."""
    positions[i, 0], positions[i, 1] = qx + radii[i] * nx, qy + radii[i] * ny


@kernel
def put_on_segment(positions, radii, segments, i, s):
    """Put body i, which the contact solver held against segment s this step, back at exactly
    its radius from it where rounding left it inside (positions only: no bounce)."""
    nx, ny, depth, qx, qy = circle_segment(positions, radii, i, segments, s)
    if depth > 0.0:
        _place_on_segment(positions, radii, i, nx, ny, qx, qy)
