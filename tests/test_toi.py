"""Time of impact (collisim.core.geometry.toi) and the discrete thin-barrier check
(collisim.narrowphase.segments): closed forms, edge cases, and properties."""
import math
from decimal import Decimal, getcontext

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st
from scipy.optimize import brentq

from collisim.core.geometry.toi import time_to_pair, time_to_point, time_to_segment, time_to_wall
from conftest import statics_step

INF = math.inf
BIG_BOX = (-1e3, -1e3, 1e3, 1e3)
getcontext().prec = 50


def exact_sqrt(x):
    return float(Decimal(x).sqrt())


def rel(a, b):
    return abs(a - b) / abs(b)


# --- walls -------------------------------------------------------------------------------

def test_wall_linear_closed_form():
    assert rel(time_to_wall(7.3, -2.1, 0.0, 0.5, -1.0, INF), (7.3 - 0.5) / 2.1) < 1e-12
    assert rel(time_to_wall(0.25, 3.0, 0.0, 9.5, 1.0, INF), (9.5 - 0.25) / 3.0) < 1e-12


def test_dropped_ball_hits_at_sqrt_2h_over_g():
    h, g = 7.25, 9.81
    assert rel(time_to_wall(0.5 + h, 0.0, -g, 0.5, -1.0, INF), float((2 * Decimal(h) / Decimal(g)).sqrt())) < 1e-12


def test_thrown_ball_hits_ceiling_closed_form():
    # 2.0 + 10 t - 4.905 t² = 6.0: the smaller root.
    v, g, gap = Decimal(10), Decimal("9.81"), Decimal(4)
    expected = float((v - (v * v - 2 * g * gap).sqrt()) / g)
    assert rel(time_to_wall(2.0, 10.0, -9.81, 6.0, 1.0, INF), expected) < 1e-12


def test_wall_touching_and_approaching_is_now():
    assert time_to_wall(0.5, -1.0, 0.0, 0.5, -1.0, INF) == 0.0
    assert time_to_wall(9.5, 1.0, 0.0, 9.5, 1.0, INF) == 0.0
    # Resting on the floor, pressed into it by gravity.
    assert time_to_wall(0.5, 0.0, -9.81, 0.5, -1.0, INF) == 0.0


def test_wall_receding_has_no_impact_until_gravity_brings_it_back():
    assert time_to_wall(0.5, 1.0, 0.0, 0.5, -1.0, INF) == INF
    assert time_to_wall(3.0, 2.0, 0.0, 0.5, -1.0, INF) == INF
    assert rel(time_to_wall(0.5, 5.0, -10.0, 0.5, -1.0, INF), 1.0) < 1e-12
    assert time_to_wall(0.5, 5.0, -10.0, 0.5, -1.0, 0.99) == INF


# --- pairs -------------------------------------------------------------------------------

def test_pair_head_on_and_oblique_closed_forms():
    assert rel(time_to_pair(10.0, 0.0, -2.0, 0.0, 2.0, INF), 4.0) < 1e-12
    # |(10 - t, 1)| = 2  ->  t = 10 - sqrt(3)
    assert rel(time_to_pair(10.0, 1.0, -1.0, 0.0, 2.0, INF), 10.0 - exact_sqrt(3)) < 1e-12
    assert time_to_pair(10.0, 1.0, -1.0, 0.0, 2.0, 8.0) == INF


def test_pair_touching_approaching_is_now_and_receding_never():
    assert time_to_pair(2.0, 0.0, -1.0, 0.0, 2.0, INF) == 0.0
    assert time_to_pair(1.5, 0.0, -1.0, 0.0, 2.0, INF) == 0.0       # overlapping, approaching
    assert time_to_pair(1.5, 0.0, 1.0, 0.0, 2.0, INF) == INF        # overlapping, separating
    assert time_to_pair(5.0, 0.0, 1.0, 0.5, 2.0, INF) == INF        # apart, receding
    assert time_to_pair(5.0, 0.0, 0.0, 1.0, 2.0, INF) == INF        # passing sideways: b = 0


@pytest.mark.parametrize("parameter, hits", [(1 - 1e-9, True), (1 + 1e-9, False)])
def test_grazing_impact_parameter_classified_exactly(parameter, hits):
    t = time_to_pair(-10.0, parameter, 1.0, 0.0, 1.0, INF)
    assert math.isfinite(t) == hits
    if hits:
        expected = 10.0 - math.sqrt((1.0 - parameter) * (1.0 + parameter))
        assert rel(t, expected) < 1e-12


finite = st.floats(-10.0, 10.0, allow_nan=False, allow_infinity=False)
positive = st.floats(0.05, 3.0)


def _check_first_contact(distance_at, t, contact, t_max):
    """distance_at(t) == contact at the impact time, and no overlap before it."""
    if t == INF:
        samples = np.linspace(0.0, t_max, 4001)
        assert min(distance_at(s) for s in samples) >= contact * (1 - 1e-7)
        return
    if t > 0.0:
        assert abs(distance_at(t) - contact) <= 1e-9 * contact
    for s in np.linspace(0.0, t, 2001)[:-1]:
        assert distance_at(s) >= contact * (1 - 1e-9)


@settings(max_examples=300, deadline=None)
@given(finite, finite, finite, finite, positive)
def test_pair_time_is_first_contact(dx, dy, vx, vy, rsum):
    assume(math.hypot(dx, dy) > rsum * (1 + 1e-6))
    t = time_to_pair(dx, dy, vx, vy, rsum, 10.0)
    _check_first_contact(lambda s: math.hypot(dx + vx * s, dy + vy * s), t, rsum, 10.0)


@settings(max_examples=300, deadline=None)
@given(finite, finite, finite, finite, finite, finite, positive)
def test_accelerated_point_time_is_first_contact(dx, dy, vx, vy, ax, ay, dist):
    assume(math.hypot(dx, dy) > dist * (1 + 1e-6))
    t = time_to_point(dx, dy, vx, vy, ax, ay, dist, 5.0)
    _check_first_contact(lambda s: math.hypot(dx + (vx + 0.5 * ax * s) * s, dy + (vy + 0.5 * ay * s) * s),
                         t, dist, 5.0)


@settings(max_examples=200, deadline=None)
@given(st.floats(0.6, 9.4), finite, st.floats(-20.0, 20.0))
def test_wall_time_is_first_contact(x, v, a):
    bound = 0.5
    t = time_to_wall(x, v, a, bound, -1.0, 10.0)
    _check_first_contact(lambda s: x + (v + 0.5 * a * s) * s, t, bound, 10.0)


def _segment_distance(px, py, segment):
    x0, y0, x1, y1 = segment
    ex, ey = x1 - x0, y1 - y0
    u = min(max(((px - x0) * ex + (py - y0) * ey) / (ex * ex + ey * ey), 0.0), 1.0)
    return math.hypot(px - x0 - u * ex, py - y0 - u * ey)


@settings(max_examples=300, deadline=None)
@given(finite, finite, finite, finite, st.sampled_from([0.0, -9.81]), positive)
def test_segment_time_is_first_contact(px, py, vx, vy, ay, r):
    segment = (-2.0, -1.0, 3.0, 1.5)
    assume(_segment_distance(px, py, segment) > r * (1 + 1e-6))
    t, nx, ny = time_to_segment(px, py, vx, vy, 0.0, ay, r, *segment, 5.0)
    position = lambda s: (px + vx * s, py + (vy + 0.5 * ay * s) * s)  # noqa: E731
    _check_first_contact(lambda s: _segment_distance(*position(s), segment), t, r, 5.0)
    if 0.0 < t < INF:
        assert abs(math.hypot(nx, ny) - 1.0) < 1e-12


# --- segments ------------------------------------------------------------------------------

SEGMENT = (-2.0, 0.0, 2.0, 0.0)


def test_segment_interior_from_above_and_below():
    t, nx, ny = time_to_segment(0.3, 5.0, 0.0, -2.0, 0.0, 0.0, 0.5, *SEGMENT, INF)
    assert rel(t, 2.25) < 1e-12 and (nx, ny) == (0.0, 1.0)
    t, nx, ny = time_to_segment(-1.0, -3.0, 0.0, 1.0, 0.0, 0.0, 0.5, *SEGMENT, INF)
    assert rel(t, 2.5) < 1e-12 and (nx, ny) == (0.0, -1.0)


def test_segment_interior_under_gravity():
    # 5 - 0.5 g t² = 0.5, the face being at y = r.
    t, nx, ny = time_to_segment(1.0, 5.0, 0.0, 0.0, 0.0, -9.81, 0.5, *SEGMENT, INF)
    assert rel(t, float((Decimal(9) / Decimal("9.81")).sqrt())) < 1e-12 and (nx, ny) == (0.0, 1.0)


def test_segment_end_cap_hit_and_normal():
    # Falling past the right end at x = 2.3: the cap at (2, 0) is hit when
    # y = sqrt(r² - 0.3²) = 0.4 (r = 0.5).
    t, nx, ny = time_to_segment(2.3, 5.0, 0.0, -1.0, 0.0, 0.0, 0.5, *SEGMENT, INF)
    assert rel(t, 4.6) < 1e-12
    assert abs(nx - 0.6) < 1e-12 and abs(ny - 0.8) < 1e-12


def test_segment_end_cap_under_gravity_matches_bracketed_root():
    px, py, vx, vy, g, r = 2.7, 4.0, -0.35, 0.5, -9.81, 0.5
    t, nx, ny = time_to_segment(px, py, vx, vy, 0.0, g, r, *SEGMENT, INF)
    gap = lambda s: math.hypot(px + vx * s - 2.0, py + (vy + 0.5 * g * s) * s) - r  # noqa: E731
    expected = brentq(gap, 0.0, 0.95, xtol=1e-16, rtol=1e-15)
    assert rel(t, expected) < 1e-10
    assert nx > 0 and ny > 0


def test_segment_missed_beside_the_end_and_hit_on_the_way_back():
    assert time_to_segment(3.0, 5.0, 0.0, -1.0, 0.0, 0.0, 0.5, *SEGMENT, INF)[0] == INF
    # Thrown up past the right end from below, it comes down on the top face.
    t, nx, ny = time_to_segment(2.7, -2.0, -1.0, 8.0, 0.0, -9.81, 0.3, *SEGMENT, INF)
    assert math.isfinite(t) and (nx, ny) == (0.0, 1.0)
    assert rel(-2.0 + (8.0 - 0.5 * 9.81 * t) * t, 0.3) < 1e-12


def test_segment_touching_but_separating_is_no_impact():
    assert time_to_segment(0.0, 0.5, 0.0, 1.0, 0.0, 0.0, 0.5, *SEGMENT, INF)[0] == INF
    assert time_to_segment(0.0, 0.5, 0.0, -1.0, 0.0, 0.0, 0.5, *SEGMENT, INF)[0] == 0.0


# --- discrete segments (narrowphase.segments) -----------------------------------------------

def test_discrete_segment_bounces_slow_particle_and_pushes_it_out():
    positions = np.array([[0.0, 0.45]])
    velocities = np.array([[1.0, -2.0]])
    _, events = statics_step(positions, velocities, [0.5], [2.0], BIG_BOX, [SEGMENT], 0.8)
    particle, segment, impulse, point = events.i, events.j, events.impulse, events.point
    assert list(particle) == [0] and list(segment) == [0]
    assert velocities[0] == pytest.approx([1.0, 1.6], abs=1e-15)
    assert impulse[0] == pytest.approx(2.0 * 3.6)
    assert positions[0] == pytest.approx([0.0, 0.5 + 0.8 * 0.05], abs=1e-15)   # as off a wall: the overshoot reflected, times e
    assert point[0] == pytest.approx([0.0, 0.0], abs=1e-15)


def test_discrete_segment_lets_a_fast_particle_tunnel():
    # One frame at 60 fps moves it 10 units: it is never within r of the segment at a
    # frame time, so discrete detection misses it (continuous detection would not).
    dt, radius = 1 / 60, 0.25
    position, velocity = np.array([[0.0, 5.0]]), np.array([[0.0, -600.0]])
    for _ in range(2):
        counts, _ = statics_step(position, velocity, [radius], [1.0], BIG_BOX, [SEGMENT], 1.0)
        assert counts.sum() == 0
        position += velocity * dt
    assert position[0, 1] < -radius
    assert math.isfinite(time_to_segment(0.0, 5.0, 0.0, -600.0, 0.0, 0.0, radius, *SEGMENT, INF)[0])


# --- the quartic's roots (geometry/roots.py) ----------------------------------------------

def _quartic_with_roots(scale, roots):
    """The 5 coefficients, lowest order first, of scale * prod(t - root)."""
    c = scale * np.poly(roots)[::-1]
    return tuple(float(x) for x in c)


@settings(max_examples=300, deadline=None)
@given(st.lists(st.integers(-1200, 1199), min_size=4, max_size=4, unique=True),
       st.lists(st.floats(0.0, 2e-4), min_size=4, max_size=4), st.floats(0.1, 10.0))
def test_first_down_crossing_is_the_first_root_where_the_quartic_turns_negative(steps, jitter, scale):
    from collisim.core.geometry.roots import first_down_crossing
    # roots in (-3, 3), over 2e-3 apart and over 1e-3 from the interval's ends 0 and 2.5, by
    # construction (filtered from free floats, too many were thrown away: a health check failed)
    roots = sorted(0.0025 * k + 0.00125 + d for k, d in zip(steps, jitter))
    coeffs = _quartic_with_roots(scale, roots)
    # p > 0 beyond the largest root, so it goes down through roots[-2] and roots[-4], up through the others
    down = [r for r in roots[::-1][1::2][::-1] if 0.0 < r <= 2.5]
    t = first_down_crossing(coeffs, 0.0, 2.5)
    if down:
        assert t == pytest.approx(down[0], abs=1e-9)
    else:
        assert t == INF


def test_first_down_crossing_of_a_double_root_and_of_a_quartic_that_stays_positive():
    from collisim.core.geometry.roots import first_down_crossing
    # (t - 1)² (t² + 1): touches zero at t = 1 without going below; the grazing contact counts
    assert first_down_crossing(_quartic_with_roots(1.0, [1.0, 1.0, 1j, -1j]), 0.0, 5.0) == pytest.approx(1.0, abs=1e-7)
    assert first_down_crossing((1.0, 0.0, 1.0, 0.0, 1.0), 0.0, 5.0) == INF   # 1 + t² + t⁴ > 0
