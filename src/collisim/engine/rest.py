"""When a body may come to rest: the rest speed both methods use by default.

A body slower than its rest speed, in a contact that holds it, may rest (and, held long enough,
sleep): engine/islands.py for the discrete step, engine/ccd/sleep.py for ccd.
"""
import math

SLEEP_HEIGHT = 1e-3   # of a body's radius: the height of a bounce that counts as resting


def default_rest_speed(gravity, radii, restitution):
    """(n,) the rest speed of each body when the scene does not state one: sqrt(2 |g|
    SLEEP_HEIGHT r), the speed of a bounce a thousandth of its radius high — 0 (never sleep)
    without gravity or when e = 1, so elastic gases and gravity-free scenes run exactly as
    without sleeping."""
    if restitution >= 1.0:
        return 0.0 * radii
    return (2.0 * math.hypot(gravity[0], gravity[1]) * SLEEP_HEIGHT * radii) ** 0.5
