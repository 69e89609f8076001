"""Sleeping never stops a body its forces would move (engine/islands.py): a box sliding slowly
down a slope whose friction almost holds it, a ball sliding down a gentle frictionless slope and
one starting to roll down it all keep to their closed forms, although each moves slower than its
rest speed for longer than the sleep time; what the contacts do hold still falls asleep."""
import numpy as np
import pytest

import collisim
from collisim import Scene, World
from collisim.engine.islands import SLEEP_TIME, new_sleep
from collisim.shapes import box

G = 9.81
FPS = 60
SECONDS = 4.0


def run(world, seconds=SECONDS, rest_speed=None):
    return collisim.simulate(Scene(world=world, fps=FPS, seconds=seconds, method="discrete", rest_speed=rest_speed))


def slope(theta, length=20.0):
    """A segment through (1, 1) rising at theta; its direction up the slope and its normal."""
    along = np.array([np.cos(theta), np.sin(theta)])
    normal = np.array([-np.sin(theta), np.cos(theta)])
    start = np.array([1.0, 1.0])
    return np.array([[*start, *(start + length * along)]]), start, along, normal


def box_on_slope(theta, friction):
    """A 1 x 0.5 box at rest on its long face, 12 units up a slope at theta."""
    segment, start, along, normal = slope(theta)
    centre = start + 12.0 * along + 0.25 * normal
    world = World([centre], polygons=[box(1.0, 0.5)], angles=theta, segments=segment, box=(0, 0, 22, 14),
                  gravity=(0, -G), restitution=0.0, friction=friction)
    return world, centre, along


def ball_on_slope(theta, friction, r=0.5):
    """A ball of radius r at rest on a slope at theta, 12 units up it."""
    segment, start, along, normal = slope(theta)
    centre = start + 12.0 * along + r * normal
    world = World([centre], radii=r, segments=segment, box=(0, 0, 22, 14), gravity=(0, -G), restitution=0.0,
                  friction=friction)
    return world, centre, along


def travelled(world_centre_along, rest_speed=None):
    """How far down the slope the body went in SECONDS."""
    world, centre, along = world_centre_along
    trajectory = run(world, rest_speed=rest_speed)
    return (trajectory.positions[-1, 0] - centre) @ -along


THETA_STEEP, THETA_GENTLE = np.radians(30.0), np.radians(1.0)
MU_SLIDE = np.tan(THETA_STEEP) - 0.011   # friction just short of holding: a = 1 % of g
CASES = {   # the body, and its acceleration down the slope in closed form
    "box sliding slowly": (lambda: box_on_slope(THETA_STEEP, MU_SLIDE),
                           G * (np.sin(THETA_STEEP) - MU_SLIDE * np.cos(THETA_STEEP))),
    "ball on a gentle frictionless slope": (lambda: ball_on_slope(THETA_GENTLE, 0.0), G * np.sin(THETA_GENTLE)),
    # a solid disc rolling: a = g sin θ / (1 + I / (m r²)) = (2/3) g sin θ
    "ball starting to roll": (lambda: ball_on_slope(THETA_GENTLE, 0.5), 2.0 / 3.0 * G * np.sin(THETA_GENTLE)),
}


@pytest.mark.parametrize("case", list(CASES))
def test_a_body_slower_than_its_rest_speed_that_its_forces_move_keeps_moving(case):
    make, acceleration = CASES[case]
    world, centre, along = make()
    rest = new_sleep(world).speed[0]
    assert acceleration * SLEEP_TIME < rest   # slower than its rest speed for longer than the sleep time
    assert travelled((world, centre, along)) == pytest.approx(0.5 * acceleration * SECONDS ** 2, rel=0.03)


def test_a_box_on_a_slope_its_friction_holds_stays_and_falls_asleep():
    theta = THETA_STEEP
    world, centre, along = box_on_slope(theta, np.tan(theta) + 0.1)
    trajectory = run(world, 2.0)
    assert np.abs(trajectory.positions[:, 0] - centre).max() < 1e-3
    asleep = np.flatnonzero(np.any(trajectory.velocities[:, 0] != 0.0, axis=1))[-1] + 1   # first frame of rest
    assert asleep <= 2 * SLEEP_TIME * FPS
    assert np.all(trajectory.positions[asleep:] == trajectory.positions[asleep])


def pile(n=10, r=0.3):
    """n balls dropped one above another, a little apart sideways, into a V of segments."""
    x = 5.0 + 0.05 * np.sin(np.arange(n))
    positions = np.column_stack([x, 2.0 + 2.2 * r * np.arange(n)])
    return World(positions, radii=r, segments=[[0.0, 4.0, 5.0, 1.0], [10.0, 4.0, 5.0, 1.0]], box=(0, 0, 10, 12),
                 gravity=(0, -G), restitution=0.2, friction=0.5)


def test_a_settled_pile_falls_asleep_within_a_few_seconds():
    trajectory = run(pile(), 4.0)
    moving = np.any(trajectory.velocities != 0.0, axis=(1, 2)) | np.any(trajectory.angular_velocities != 0.0,
                                                                          axis=1)
    asleep = np.flatnonzero(moving)[-1] + 1
    assert asleep <= 3.0 * FPS
    assert np.all(trajectory.positions[asleep:] == trajectory.positions[asleep])


def test_a_ball_thrown_at_a_sleeping_box_wakes_it_and_pushes_it():
    """A box asleep on the floor; a ball thrown from the left lands short of it, rolls on and
    pushes it (the island wakes when an awake body comes within reach: engine/islands.py)."""
    world = World([(5.0, 0.25), (0.5, 3.0)], velocities=[(0.0, 0.0), (3.0, 0.0)], polygons=[box(1.0, 0.5), None],
                  radii=0.3, box=(0, 0, 10, 10), gravity=(0, -G), restitution=0.0, friction=0.2)
    trajectory = run(world, 2.5)
    x = trajectory.positions[:, 0, 0]
    reach = int(np.argmax(trajectory.positions[:, 1, 0] > 4.5 - 0.3 - 0.05))   # the ball at the box's face
    assert reach > 2 * SLEEP_TIME * FPS
    assert np.all(trajectory.velocities[reach - 5:reach - 1, 0] == 0.0)         # the box asleep until then
    assert x[-1] > 5.0 + 0.05                                                    # woken and pushed
