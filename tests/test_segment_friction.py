"""Discs on segments, in the discrete method, held by the contact solver with friction as on the
box floor (response/rows.circle_segment_manifolds): a disc slipping or rolling down a segment
slope follows the closed forms and logs no collision while it slides; a disc dropped on a segment
still bounces with its restitution, and that impact is one collision.

Before the fix a disc held by a segment could end a step a rounding error away from it; then it
was not looked up for rows the next step, fell into the segment and was bounced off it without
friction, and the bounce was logged (10 to 21 of 60 frames): at 20 degrees and mu = 0.1 the
acceleration came out 8.9 % high and the angular acceleration 24 % low."""
import numpy as np
import pytest

import collisim
from collisim import Scene, World
from collisim.core.kinds import PAIR, SEGMENT

G = 9.81
R = 0.5
FPS = 60


def run(world, seconds=1.0):
    return collisim.simulate(Scene(world=world, fps=FPS, seconds=seconds, method="discrete"))


def on_segment_slope(theta, friction, lift=0.0):
    """A disc at rest on (or `lift` above) a segment rising at theta: (world, its centre, the unit
    vector down the slope)."""
    up = np.array([np.cos(theta), np.sin(theta)])
    normal = np.array([-np.sin(theta), np.cos(theta)])
    start = np.array([1.0, 1.0])
    centre = start + 20.0 * up + (R + lift) * normal
    world = World([centre], radii=R, segments=[[*start, *(start + 30.0 * up)]], box=(0, 0, 32, 20),
                  gravity=(0, -G), restitution=0.0, friction=friction)
    return world, centre, -up


def on_tilted_floor(theta, friction):
    """The same disc on the box floor with gravity tilted by theta (down the slope is -x)."""
    centre = np.array([25.0, R])
    world = World([centre], radii=R, box=(0, 0, 30, 10), gravity=(-G * np.sin(theta), -G * np.cos(theta)),
                  restitution=0.0, friction=friction)
    return world, centre, np.array([-1.0, 0.0])


def rates(trajectory, down):
    """The disc's acceleration down the slope and its angular acceleration (magnitude), fitted
    over the run; its speed down the slope and its turning rate at each frame."""
    t = trajectory.times
    speed, turning = trajectory.velocities[:, 0] @ down, np.abs(trajectory.angular_velocities[:, 0])
    return np.polyfit(t, speed, 1)[0], np.polyfit(t, turning, 1)[0], speed, turning


def collisions(trajectory):
    kinds = trajectory.events.kind
    return int(np.sum((kinds == PAIR) | (kinds == SEGMENT)))


@pytest.mark.parametrize("degrees", [20, 30])
def test_a_disc_slipping_down_a_segment_follows_the_closed_form(degrees):
    theta, mu = np.radians(degrees), 0.1   # mu < tan(theta) / 3: it slips
    world, _, down = on_segment_slope(theta, mu)
    trajectory = run(world)
    a, alpha, _, _ = rates(trajectory, down)
    assert a == pytest.approx(G * (np.sin(theta) - mu * np.cos(theta)), rel=0.01)
    assert alpha == pytest.approx(2 * mu * G * np.cos(theta) / R, rel=0.02)   # solid disc: I = m r² / 2
    assert collisions(trajectory) == 0          # sliding along it is not a collision
    floor_a, floor_alpha, _, _ = rates(run(on_tilted_floor(theta, mu)[0]), np.array([-1.0, 0.0]))
    assert a == pytest.approx(floor_a, rel=0.01) and alpha == pytest.approx(floor_alpha, rel=0.01)


@pytest.mark.parametrize("degrees", [20, 30])
def test_a_disc_rolling_down_a_segment_follows_the_closed_form(degrees):
    theta, mu = np.radians(degrees), 0.5   # mu > tan(theta) / 3: it rolls
    world, _, down = on_segment_slope(theta, mu)
    trajectory = run(world)
    a, _, speed, turning = rates(trajectory, down)
    assert a == pytest.approx(2.0 / 3.0 * G * np.sin(theta), rel=0.01)
    moving = speed > 0.1
    np.testing.assert_allclose(turning[moving] * R, speed[moving], rtol=0.005)   # v = ω r: no slip
    assert collisions(trajectory) == 0
    floor_a, _, _, _ = rates(run(on_tilted_floor(theta, mu)[0]), np.array([-1.0, 0.0]))
    assert a == pytest.approx(floor_a, rel=0.01)


def test_a_disc_landing_on_a_segment_slope_logs_the_landing_alone():
    """Dropped a fifth of its radius onto the slope (e = 0): one collision, its landing, and none
    while it slides on."""
    world, _, _ = on_segment_slope(np.radians(30), 0.1, lift=0.2 * R)
    events = run(world).events
    landings = events.time[(events.kind == SEGMENT) | (events.kind == PAIR)]
    assert len(landings) == 1 and landings[0] < 0.2


def test_a_disc_dropped_on_a_segment_bounces_with_its_restitution():
    """From h = 2 above a segment floor at e = 0.8: one collision, and the rebound speed, read
    from the height it climbs to before it lands again, is e times the impact speed, as off the
    box floor (reflecting the step's end velocity, which had fallen up to a step's travel past
    the contact, it came back 1.8 % fast)."""
    e, h, floor = 0.8, 2.0, 1.0
    world = World([(5.0, floor + R + h)], radii=R, segments=[[0.0, floor, 10.0, floor]], box=(0, 0, 10, 10),
                  gravity=(0, -G), restitution=e, friction=0.5)
    landing = np.sqrt(2 * h / G)
    again = landing + 2 * e * np.sqrt(2 * G * h) / G   # the second landing
    trajectory = run(world, seconds=np.ceil(FPS * 0.5 * (landing + again) + 3) / FPS)   # past the apex
    assert collisions(trajectory) == 1
    assert int(np.sum(trajectory.events.kind == SEGMENT)) == 1
    after = trajectory.times > landing
    apex = trajectory.positions[after, 0, 1].max() - floor - R
    assert np.sqrt(2 * G * apex) == pytest.approx(e * np.sqrt(2 * G * h), rel=0.002)   # the frames' sampling of the apex
