"""Sleeping islands of the discrete method (engine/islands.py): bodies at rest sleep as a whole,
cost nothing, keep pressing their walls, and wake when something comes near."""
import numpy as np
import pytest

import collisim
from collisim import Scene, World
from collisim.engine.discrete import DiscreteStepper
from collisim.engine.islands import SLEEP_TIME, new_sleep
from collisim.core.kinds import SUPPORT
from collisim.shapes import box

G = 9.81
FPS = 60


def run(world, seconds, broadphase="auto", rest_speed=None):
    return collisim.simulate(Scene(world=world, fps=FPS, seconds=seconds, broadphase=broadphase,
                                   rest_speed=rest_speed))


def stack_world(count=4, h=0.5, restitution=0.0, extra=()):
    """count boxes 1 x h standing on the floor, and the balls `extra` ((x, y, vx, vy) each)."""
    positions = [(5.0, h / 2 + h * k) for k in range(count)] + [(x, y) for x, y, _, _ in extra]
    velocities = [(0.0, 0.0)] * count + [(vx, vy) for _, _, vx, vy in extra]
    return World(positions, velocities=velocities, polygons=[box(1.0, h)] * count + [None] * len(extra),
                 radii=0.2, box=(0, 0, 10, 10), gravity=(0, -G), restitution=restitution, friction=0.5)


def sleepers(world, frames, rest_speed=None):
    """The stepper after `frames` frames, and how many bodies sleep after each."""
    stepper = DiscreteStepper(world, FPS, rest_speed=rest_speed)
    asleep = []
    for _ in range(frames):
        stepper.run(1)
        asleep.append(int(stepper.sleep.asleep.sum()))
    return stepper, np.array(asleep)


def test_a_resting_stack_falls_asleep_together_after_the_sleep_time_and_then_does_not_move():
    world = stack_world()
    stepper, asleep = sleepers(world, 90)
    assert set(asleep.tolist()) == {0, world.n}                     # the island sleeps as a whole
    first = int(np.argmax(asleep > 0)) + 1                            # frames until it slept
    assert SLEEP_TIME * FPS <= first <= 2 * SLEEP_TIME * FPS
    frames, _ = stepper.run(30)
    assert np.all(frames.velocities == 0.0) and np.all(frames.angular_velocities == 0.0)
    assert np.all(frames.positions == frames.positions[0])           # exactly where they fell asleep


def test_a_sleeping_ball_presses_the_floor_with_its_weight():
    world = World([(5.0, 0.5)], radii=0.5, masses=2.0, box=(0, 0, 10, 10), gravity=(0, -G), restitution=0.5)
    seconds = 3.0
    trajectory = run(world, seconds)
    assert np.all(trajectory.velocities[-60:] == 0.0)
    events = trajectory.events
    floor = events.kind == SUPPORT
    assert len(events) == floor.sum() and np.all(events.j == 2)
    assert events.impulse.sum() / seconds == pytest.approx(2.0 * G, rel=1e-9)   # asleep 5/6 of the time


def test_a_falling_ball_wakes_the_sleeping_stack_and_the_stack_holds():
    """The ball is let go high above the stack; the stack is asleep before it lands, wakes,
    takes the blow and holds (its warm-start memory kept through its sleep), and sleeps again."""
    world = stack_world(extra=[(5.0, 6.0, 0.0, 0.0)])
    stepper = DiscreteStepper(world, FPS)
    frames = [stepper.run(1)[0] for _ in range(240)]
    positions = np.concatenate([f.positions for f in frames])
    landing = int(np.argmax(positions[:, 4, 1] < 2.0 + 0.2 + 0.05))   # the ball reaches the top box
    assert landing > SLEEP_TIME * FPS + 5
    moved = np.abs(positions[landing:, :4] - positions[landing - 1, :4]).max()
    assert moved > 0.0                                                # woken: the stack felt the ball
    assert moved < 0.02 * 0.5                                         # and held: under 2 % of a box
    assert stepper.sleep.asleep[:4].all()                             # asleep again at the end


def test_a_woken_stack_gains_no_energy():
    """Woken bodies start from rest: from the frame before the ball lands on the sleeping stack,
    the energy only falls (the position correction may lift bodies by a fraction of their slop:
    1e-3 of the energy; a body woken with a stale velocity or impulse would be far above)."""
    world = stack_world(restitution=0.3, extra=[(5.3, 6.0, 0.0, 0.0)])
    trajectory = run(world, 4.0)
    kinetic = 0.5 * (world.masses * (trajectory.velocities ** 2).sum(-1)).sum(-1) + \
        0.5 * (world.inertias * trajectory.angular_velocities ** 2).sum(-1)
    total = kinetic + (world.masses * G * trajectory.positions[:, :, 1]).sum(-1)
    moved = np.abs(np.diff(trajectory.positions[:, :4], axis=0)).max(axis=(1, 2)) > 0
    woke = int(np.flatnonzero(moved[int(SLEEP_TIME * FPS) + 20:])[0]) + int(SLEEP_TIME * FPS) + 20
    assert total[woke:].max() <= total[woke] * (1 + 1e-3)


def test_nothing_sleeps_without_gravity_with_e_1_or_with_rest_speed_0():
    still = World([(2.0, 2.0), (5.0, 5.0)], radii=0.5, box=(0, 0, 10, 10), restitution=0.5)
    assert not new_sleep(still).on                                               # no gravity
    assert not new_sleep(stack_world(restitution=1.0)).on                         # elastic
    assert not new_sleep(stack_world(), rest_speed=0.0).on                        # turned off
    assert new_sleep(stack_world()).on
    _, asleep = sleepers(stack_world(), 60, rest_speed=0.0)
    assert asleep.max() == 0


def test_a_world_that_never_sleeps_types_its_sleep_as_never():
    # the step then compiles none of the sleeping (sleep_paths.py): its `on` is typed None
    from numba import typeof

    from collisim.engine.sleep_paths import _never
    still = World([(2.0, 2.0), (5.0, 5.0)], radii=0.5, box=(0, 0, 10, 10), restitution=0.5)
    assert _never(typeof(new_sleep(still)))
    assert _never(typeof(new_sleep(stack_world(), rest_speed=0.0)))
    assert not _never(typeof(new_sleep(stack_world())))


def test_sleeping_removes_at_most_the_rest_speeds_energy():
    world = stack_world(count=1)
    stepper = DiscreteStepper(world, FPS)
    speed = stepper.sleep.speed[0]
    before = None
    for _ in range(60):
        was_awake = not stepper.sleep.asleep[0]
        v, w = stepper.bodies.velocities[0].copy(), stepper.bodies.angular_velocities[0]
        stepper.run(1)
        if was_awake and stepper.sleep.asleep[0]:
            before = 0.5 * world.masses[0] * (v @ v) + 0.5 * world.inertias[0] * w * w
    r = world.radii[0]
    assert before is not None
    assert before <= 0.5 * world.masses[0] * speed ** 2 + 0.5 * world.inertias[0] * (speed / r) ** 2


def test_sleeping_gives_the_same_bytes_under_the_grid_as_under_brute_force_and_in_any_block_size():
    # (a broad phase that keeps its state from call to call, sweep and prune, is held to brute
    # force's pairs after bodies jump between calls, as sleepers do when they wake:
    # test_broadphase.py)
    world = stack_world(extra=[(5.0, 6.0, 0.0, 0.0), (1.0, 0.2, 0.0, 0.0)])
    reference = run(world, 3.0, broadphase="brute")
    assert run(world, 3.0, broadphase="grid").positions.tobytes() == reference.positions.tobytes()
    stepper = DiscreteStepper(world, FPS)
    blocks = np.concatenate([stepper.run(k)[0].positions for k in (1, 50, 7, 122)])
    assert blocks.tobytes() == reference.positions[1:].tobytes()


def test_a_world_fully_asleep_records_and_logs_the_same_in_every_block_size():
    # a step of a world whose every body sleeps only logs the support (engine/discrete.py): the
    # frames, the funnel's counts and every step's support must be those of the full step
    # (the block of 62 frames falls asleep on the way; the last is asleep from its start)
    world = stack_world(extra=[(1.0, 0.2, 0.0, 0.0)])
    reference = run(world, 3.5)
    stepper = DiscreteStepper(world, FPS)
    blocks = [stepper.run(k) for k in (1, 50, 7, 60, 62, 30)]
    assert stepper.sleep.asleep.all()
    for name in ("positions", "velocities", "angles", "hierarchy"):
        joined = np.concatenate([getattr(frames, name) for frames, _ in blocks])
        assert joined.tobytes() == getattr(reference, name)[1:].tobytes(), name
    events = collisim.Events.concatenate([events for _, events in blocks])
    for name in ("time", "kind", "i", "j", "impulse", "point"):
        assert getattr(events, name).tobytes() == getattr(reference.events, name).tobytes(), name
    last = reference.events.time > 2.51                              # asleep: the support alone, every step
    steps = np.unique(reference.events.time[last])
    assert np.all(reference.events.kind[last] == SUPPORT)
    assert steps.tolist() == [k * (1.0 / FPS) for k in range(151, 211)]
    # the soft step's springs (response/soft_step.py) are still settling by 1e-4 when the world sleeps
    assert reference.events.impulse[last].sum() / 1.0 == pytest.approx(world.masses.sum() * G, rel=5e-4)


def test_a_block_of_a_world_asleep_holds_its_state_once():
    # the frames of a world asleep from the block's start are one state: a streamed block of them
    # holds that state's memory once, not once a frame (simulate's trajectory keeps every frame)
    world = stack_world(extra=[(1.0, 0.2, 0.0, 0.0)])
    stepper = DiscreteStepper(world, FPS)
    stepper.run(180)
    assert stepper.sleep.asleep.all()
    frames, _ = stepper.run(64)
    for name in ("positions", "velocities", "angles", "angular_velocities"):
        rows = getattr(frames, name)
        assert rows.shape[0] == 64 and np.shares_memory(rows[0], rows[63]), name
    trajectory = run(world, (180 + 64) / FPS)
    assert frames.positions.tobytes() == trajectory.positions[181:].tobytes()
    assert not np.shares_memory(trajectory.positions[181], trajectory.positions[244])


def test_the_funnel_counts_the_pairs_of_sleepers():
    from collisim.engine.hierarchy import hierarchy
    world = stack_world()
    trajectory = run(world, 1.5)
    for frame in (10, 89):                                            # awake, then asleep
        counts = hierarchy(world, trajectory.positions[frame], trajectory.angles[frame])["counts"]
        assert trajectory.hierarchy[frame].tolist() == counts.tolist()


def test_a_floor_of_boxes_falls_asleep_with_two_support_rows_each():
    """Twenty boxes lying apart on the floor: each its own island, each resting on two points."""
    world = World([(0.6 + 1.2 * k, 0.25) for k in range(20)], polygons=[box(1.0, 0.5)] * 20,
                  box=(0, 0, 25, 5), gravity=(0, -G), restitution=0.0)
    stepper, asleep = sleepers(world, 60)
    assert asleep[-1] == world.n
    assert stepper.sleep.carried_count[0] == 2 * world.n
