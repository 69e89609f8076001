"""ccd under gravity: bodies at rest, the supports that carry them, and what they log."""
import math

import numpy as np
import pytest

import collisim
from collisim.analysis import metrics
from collisim.engine.ccd.events import simulate_events
from collisim.core.geometry.segment import segment_contact
from collisim.core.kinds import N_WALLS, PAIR, SEGMENT, SUPPORT, WALL
from collisim.pipeline import scene_chapters
from collisim.render.timeline import draw_frame, make_players

G = 9.81


def ccd(positions, radius=0.5, restitution=0.5, seconds=3.0, segments=None, velocities=None, box=(0, 0, 10, 10)):
    world = collisim.World(positions=positions, velocities=velocities, radii=radius, box=box,
                           gravity=(0, -G), restitution=restitution, segments=segments)
    return world, collisim.simulate(collisim.Scene(world=world, fps=60, seconds=seconds, method="ccd"))


def test_the_floor_carries_the_weight_of_a_body_at_rest_on_it():
    world, traj = ccd([[5.0, 0.5]])
    perimeter = 2 * (10 + 10)
    weight = world.masses[0] * G
    assert metrics.wall_pressure(traj) * perimeter == pytest.approx(weight, rel=1e-9)
    # m·g·dt each frame, on the floor, under the body, a support and not a collision
    assert np.all(traj.events.kind == SUPPORT) and np.all(traj.events.j == 2)
    floor = traj.events.impulse
    np.testing.assert_allclose(floor, weight / 60, rtol=1e-9)
    assert len(floor) == traj.frames and traj.wall_collisions.sum() == 0
    np.testing.assert_allclose(traj.events.point, np.tile([5.0, 0.0], (traj.frames, 1)))


def test_bounces_then_rest_give_the_floor_the_momentum_balance():
    # the floor's impulse over [0, T] is m g T + m (v_y(T) - v_y(0)): bounces and rest together
    world, traj = ccd([[5.0, 6.0]], restitution=0.6, seconds=6.0)
    assert traj.velocities[-1, 0, 1] == 0.0 and traj.positions[-1, 0, 1] == 0.5   # at rest by then
    duration = traj.times[-1]
    bounces, support = (traj.events.kind == WALL), (traj.events.kind == SUPPORT)
    assert np.all(traj.events.j[bounces | support] == 2) and bounces.sum() == traj.wall_collisions.sum() > 3
    floor = traj.events.impulse[bounces | support].sum()
    assert floor == pytest.approx(world.masses[0] * G * duration, rel=1e-9)
    assert metrics.wall_pressure(traj) * 2 * (10 + 10) * duration == pytest.approx(floor, rel=1e-12)


def test_a_segment_carries_a_ball_at_rest_and_a_vee_carries_a_wedged_ball():
    shelf = [[2.0, 4.0, 8.0, 4.0]]
    world, traj = ccd([[5.0, 4.5]], segments=shelf)
    impulse = traj.events.impulse[(traj.events.kind == SEGMENT) | (traj.events.kind == SUPPORT)].sum()
    assert impulse == pytest.approx(world.masses[0] * G * traj.times[-1], rel=1e-9)
    assert np.all(traj.events.j[traj.events.kind == SUPPORT] == N_WALLS + 0)   # the shelf, segment 0

    vee = np.array([[1.0, 6.0, 5.0, 2.0], [5.0, 2.0, 9.0, 6.0]])
    world, traj = ccd([[3.0, 8.0]], segments=vee, velocities=[[0.3, 0.0]], seconds=10.0)
    assert np.all(traj.velocities[-1] == 0.0)
    # from when it is wedged on, the two sides' impulses add up to the weight: m g per second
    late = (traj.events.kind == SUPPORT) & (traj.events.time > 8.0)
    assert not np.any((traj.events.kind == SEGMENT) & (traj.events.time > 8.0))   # no more impacts
    lift = 0.0
    for j, impulse in zip(traj.events.j[late], traj.events.impulse[late]):
        ny = segment_contact(*traj.positions[-1, 0], vee[j - N_WALLS])[1]
        lift += impulse * ny
    assert lift == pytest.approx(world.masses[0] * G * 2.0, rel=1e-9)


def drawn(scene, frames, flash):
    """The player's canvases of `frames` with the impact rings on or off (no HUD)."""
    scene = scene.replace(render=collisim.RenderSettings(hud=False, flash=flash))
    size = (480, 480)
    players = make_players(scene_chapters(scene)[0], size, scene.fps)
    canvases = []
    for f in range(max(frames) + 1):
        canvas = np.zeros((size[1], size[0], 3), np.uint8)
        draw_frame(canvas, players, f)
        if f in frames:
            canvases.append(canvas)
    return canvases


def test_a_body_at_rest_flashes_no_ring_but_its_first_impact_does():
    # dropped with e = 0 from 0.1 above the floor: it lands at t = sqrt(0.2 / g) = 0.143 s (frame
    # 9), rests there, and from then on only its support is logged, every frame
    world = collisim.World(positions=[[5.0, 0.6]], radii=0.5, box=(0, 0, 10, 10), gravity=(0, -G), restitution=0.0)
    scene = collisim.Scene(world=world, fps=60, seconds=1.0, method="ccd")
    traj = collisim.simulate(scene)
    impacts = traj.events.time[traj.events.kind == WALL]
    assert len(impacts) == 1 and impacts[0] == pytest.approx(math.sqrt(0.2 / G), rel=1e-12)
    assert np.all(traj.events.kind[traj.events.time > impacts[0]] == SUPPORT)
    landing = int(math.ceil(impacts[0] * 60))
    frames = [landing, landing + 12, 40, 60]   # the landing, then after its ring has faded (FLASH_SECONDS)
    rings, plain = drawn(scene, frames, True), drawn(scene, frames, False)
    assert np.any(rings[0] != plain[0])                      # the landing flashes
    for with_rings, without in zip(rings[1:], plain[1:]):    # resting does not, though logged each frame
        np.testing.assert_array_equal(with_rings, without)
    # the floor's impulse over [0, T] is m g T + m (v(T) - v(0)) = m g T: the pressure is still m·g
    assert metrics.wall_pressure(traj) * 2 * (10 + 10) == pytest.approx(world.masses[0] * G, rel=1e-9)


def test_tc_model_makes_collisions_within_tc_of_the_last_elastic():
    # e = 0.5, no gravity: A (speed 8) hits B, then B (speed 6) hits C 1/60 s later. With tc = 10 s
    # that second collision comes within tc of B's first and is elastic: C leaves at 6 and B stops;
    # without, C leaves at 4.5 and B keeps 1.5. A ball that only meets walls keeps e.
    common = ([[2.0, 5.0], [5.0, 5.0], [6.1, 5.0]], [[8.0, 0.0], [0.0, 0.0], [0.0, 0.0]], (0.0, 0.0), [0.5] * 3,
              [1.0] * 3, (0.0, 0.0, 20.0, 10.0), 0.5, None, 0.01, 28)
    with_tc = simulate_events(*common, tc=10.0)
    assert len(with_tc.time) == 2
    np.testing.assert_allclose(with_tc.velocities[-1, :, 0], [2.0, 0.0, 6.0], rtol=1e-12, atol=1e-12)
    without = simulate_events(*common, tc=0.0)
    np.testing.assert_allclose(without.velocities[-1, :, 0], [2.0, 1.5, 4.5], rtol=1e-12, atol=1e-12)
    walls = ([[5.0, 5.0]], [[8.0, 0.0]], (0.0, 0.0), [0.5], [1.0], (0.0, 0.0, 10.0, 10.0), 0.5, None, 0.1, 80)
    assert np.abs(simulate_events(*walls, tc=10.0).velocities[-1, 0, 0]) <= 1.0   # 8 -> 4 -> 2 -> 1
    # but a ball hit by another hits a wall within tc elastically: B leaves A at 6 and meets the
    # right wall 1/4 s later, coming back at 6 (at 3 without tc), before A reaches it again
    relay = ([[2.0, 5.0], [8.0, 5.0]], [[8.0, 0.0], [0.0, 0.0]], (0.0, 0.0), [0.5] * 2, [1.0] * 2,
             (0.0, 0.0, 10.0, 10.0), 0.5, None, 0.01, 95)
    np.testing.assert_allclose(simulate_events(*relay, tc=10.0).velocities[-1, :, 0], [2.0, -6.0], rtol=1e-12)
    np.testing.assert_allclose(simulate_events(*relay, tc=0.0).velocities[-1, :, 0], [2.0, -3.0], rtol=1e-12)


def test_contact_model_parameters_are_checked():
    world = collisim.World(positions=[[5.0, 1.0]], box=(0, 0, 10, 10), gravity=(0, -G), restitution=0.5)
    with pytest.raises(ValueError, match="rest_speed"):
        collisim.Scene(world=world, method="ccd", rest_speed=-1.0)
    with pytest.raises(ValueError, match="tc"):
        collisim.Scene(world=world, method="ccd", tc="1")


def largest_overlap(traj):
    """The largest overlap of any two bodies in any frame, in radii of the smaller."""
    p, r = traj.positions, traj.radii
    i, j = np.triu_indices(len(r), 1)
    d = np.hypot(*(p[:, i] - p[:, j]).transpose(2, 0, 1))
    return float(((r[i] + r[j] - d) / np.minimum(r[i], r[j])).max())


def test_a_woken_sleeper_moves_on_from_where_it_slept():
    # a ball in the cradle of two on the floor of a box two diameters wide (the walls hold the two
    # apart; on an open frictionless floor the cradle would push them aside) falls asleep; a ball
    # dropped from the top hits it and wakes it: it must go on from where it slept (it once fell
    # for all the time it had slept, through the balls under it)
    r = 0.5
    positions = [[0.5, r], [1.5, r], [1.0, r + math.sqrt(3) * r + 0.05], [1.0, 9.5]]
    world = collisim.World(positions, radii=r, box=(0, 0, 2, 10), gravity=(0, -G), restitution=0.5)
    traj = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=2.0, method="ccd", rest_speed=0.1))
    # the two on the floor, squeezed between it, the walls and the falling cradle, fall asleep on the
    # floor as they hit it (sleep.doze) instead of rattling in place until the event budget runs out
    assert not traj.approximate.any()
    asleep = traj.velocities[60:72, :3]
    assert np.all(asleep == 0.0)                                      # settled and asleep before the hit
    cradle = traj.positions[60, 2, 1]
    assert cradle == pytest.approx(r + math.sqrt(3) * r, abs=1e-9)
    hit = traj.events.time[(traj.events.kind == PAIR) & (traj.events.j == 3)][0]
    assert hit == pytest.approx(math.sqrt(2 * (9.5 - cradle - 2 * r) / G), rel=1e-12)   # free fall, undisturbed
    # the hit wakes it; held by the two under it (the walls hold them) it cannot move, and sleeps again
    assert traj.positions[:, 2, 1].min() >= cradle - 1e-9              # never below where it slept
    assert largest_overlap(traj) < 1e-9


def test_sleeping_is_on_by_default_only_under_gravity_and_when_inelastic():
    from collisim.engine.rest import default_rest_speed
    radii = np.array([0.45, 0.2])
    np.testing.assert_allclose(default_rest_speed((0.0, -G), radii, 0.5), np.sqrt(2 * G * 1e-3 * radii), rtol=1e-15)
    assert np.all(default_rest_speed((0.0, 0.0), radii, 0.5) == 0.0)   # no gravity: a gas never sleeps
    assert np.all(default_rest_speed((0.0, -G), radii, 1.0) == 0.0)    # elastic: no rest to come to


def test_the_tc_model_is_on_by_default_only_where_bodies_sleep():
    from collisim.engine.ccd.resolve import default_tc
    from collisim.engine.rest import default_rest_speed
    from collisim.engine.ccd.stepper import CCDStepper
    radii = np.array([0.45, 0.2])
    slowest = np.sqrt(2 * G * 1e-3 * 0.2)   # the smaller body's rest speed
    assert default_tc((0.0, -G), default_rest_speed((0.0, -G), radii, 0.5)) == pytest.approx(0.01 * slowest / G,
                                                                                              rel=1e-14)
    assert default_tc((0.0, 0.0), default_rest_speed((0.0, 0.0), radii, 0.5)) == 0.0   # a gas: off
    assert default_tc((0.0, -G), default_rest_speed((0.0, -G), radii, 1.0)) == 0.0     # elastic: off
    world = collisim.World([[2.0, 2.0], [5.0, 2.0]], radii=radii, box=(0, 0, 10, 10), gravity=(0, -G),
                           restitution=0.5)
    assert CCDStepper(world, 60, 10).loop.env.tc == pytest.approx(0.01 * slowest / G, rel=1e-14)
    assert CCDStepper(world, 60, 10, rest_speed=0.0).loop.env.tc == 0.0                # nothing sleeps: off
    assert CCDStepper(world, 60, 10, tc=0.0).loop.env.tc == 0.0                         # stated: kept


def test_a_small_inelastic_pile_falls_asleep_without_overlap():
    """24 balls, e = 0.5, dropped into a box 6 diameters wide, sleeping by default: by 2 s every one
    is asleep, and no two ever overlap (the body of a woken sleeper once fell for all the time it had slept)."""
    rng = np.random.default_rng(3)
    n = 24
    x = (np.arange(n) % 6 + 0.5) * (6.0 / 6) + rng.uniform(-0.05, 0.05, n)
    y = 1.0 + (np.arange(n) // 6) * 1.2
    world = collisim.World(np.column_stack([x, y]), radii=0.45, box=(0, 0, 6, 8), gravity=(0, -G), restitution=0.5)
    traj = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=4.0, method="ccd"))   # default rest speed
    assert not traj.approximate.any()
    assert np.all(traj.velocities[120:] == 0.0)                         # asleep: every body still, exactly
    assert np.all(traj.positions[120:] == traj.positions[-1])
    assert len(traj.events) == 0 or traj.events.time[traj.events.kind != SUPPORT].max() < 2.0
    assert largest_overlap(traj) < 1e-9


def test_an_inelastic_pile_of_sixty_leaning_on_each_other_falls_asleep():
    """60 balls, e = 0, dropped in rows into a box 6 diameters wide: balls that lean on each other
    (arches, rows pressed together) cannot wait for one another to sleep first; by 3 s the pile is
    still, exactly, and no two balls ever overlap."""
    rng = np.random.default_rng(1)
    n, r, columns = 60, 0.5, 6
    pitch = 2 * r * columns / (columns - 1)
    x = (np.arange(n) % (columns - 1) + 0.5) * pitch + rng.uniform(-0.1, 0.1, n) * r
    y = 3 * r + (np.arange(n) // (columns - 1)) * 2.5 * r
    world = collisim.World(np.column_stack([x, y]), rng.normal(0, 0.5, (n, 2)), r, box=(0, 0, 6, y.max() + 2 * r),
                           gravity=(0, -G), restitution=0.0)
    traj = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=3.5, method="ccd", rest_speed=0.099))
    assert not traj.approximate.any()
    assert np.all(traj.velocities[180:] == 0.0) and np.all(traj.positions[180:] == traj.positions[-1])
    assert largest_overlap(traj) < 1e-9
    # asleep, the whole pile weighs on the floor (carried.py), leaning balls and all
    weight = world.masses.sum() * G
    for frame in (190, 210):
        assert _support_per_frame(traj, frame)[2] == pytest.approx(weight, rel=1e-9)


def _support_per_frame(traj, frame):
    """The SUPPORT impulse each wall gave during frame `frame`, as a force (impulse × fps)."""
    ev = traj.events
    during = (ev.time > traj.times[frame - 1]) & (ev.time <= traj.times[frame]) & (ev.kind == SUPPORT)
    impulses = np.array([ev.impulse[during & (ev.j == wall)].sum() for wall in range(N_WALLS)])
    return impulses / (traj.times[1] - traj.times[0])


def test_a_sleeping_pile_gives_the_floor_its_whole_weight():
    """Rows of 5, 4, 5 and 4 balls in a box 5 diameters wide fall asleep; the floor then carries
    all 18, not only the bottom row (the weight of the rows above is carried down, carried.py),
    and the side walls push equally."""
    r = 0.5
    positions = [[r + 2 * r * c + (r if row % 2 else 0.0), r + row * (math.sqrt(3) * r + 0.02)]
                 for row in range(4) for c in range(5 - row % 2)]
    world, traj = ccd(positions, radius=r, restitution=0.5, seconds=3.0, box=(0, 0, 5, 8))
    weight = world.masses.sum() * G
    assert np.all(traj.velocities[90:] == 0.0) and not traj.approximate.any()
    for frame in (100, 150, 180):
        left, right, floor, top = _support_per_frame(traj, frame)
        assert floor == pytest.approx(weight, rel=1e-9) and top == 0.0
        assert left == pytest.approx(right, rel=1e-9) and left > 0.0


def test_a_ball_asleep_in_a_cradle_pushes_the_walls_apart_by_the_statics_of_its_two_supports():
    """A ball asleep on two that fill a box two diameters wide: each lower ball takes m g / (2 cos 30°)
    along the line of centres, so the floor carries 3 m g and each wall m g tan 30° / 2."""
    r = 0.5
    cradle = [[0.5, r], [1.5, r], [1.0, r + math.sqrt(3) * r + 0.05]]
    world, traj = ccd(cradle, radius=r, seconds=2.0, box=(0, 0, 2, 10))
    assert np.all(traj.velocities[60:] == 0.0)
    m = world.masses[0]
    left, right, floor, top = _support_per_frame(traj, 100)
    assert floor == pytest.approx(3 * m * G, rel=1e-9)
    assert left == pytest.approx(m * G * math.tan(math.pi / 6) / 2, rel=1e-9)
    assert right == pytest.approx(left, rel=1e-12)


def test_a_sleeper_left_touching_nothing_wakes_and_falls():
    """A body asleep in mid-air — as one frozen leaning on a body that has since moved away —
    is held up by nothing: at the next frame time it wakes and falls (carried.py); before, it
    hung there for ever, its weight on nothing."""
    from collisim.engine.ccd.bodies import fall_asleep
    from collisim.engine.ccd.events import run, start_event_loop
    loop = start_event_loop([[5.0, 5.0]], [[0.0, 0.0]], (0.0, -G), [0.5], [1.0], (0, 0, 10, 10), 0.5, None, 1.0)
    fall_asleep(loop.bodies, 0)
    loop.supports.sleeping[0] = True
    positions, velocities = np.empty((30, 1, 2)), np.empty((30, 1, 2))
    run(loop, 1 / 60, 1, 30, 100_000, positions, velocities, np.zeros((30, 3), np.int64), np.zeros(30, np.bool_))
    assert positions[0, 0, 1] == 5.0 and not loop.bodies.asleep[0]          # woken at the first frame time
    fallen = 0.5 * G * (29 / 60) ** 2                                        # and falling freely since
    assert positions[-1, 0, 1] == pytest.approx(5.0 - fallen, rel=1e-12)


def test_a_frictionless_pyramid_of_three_collapses_as_without_sleeping():
    """Two balls at rest on the floor and one on top of them: a frictionless floor holds the
    bottom two up, not in place, so the top one pushes them apart and ends on the floor, as
    it does with sleeping off (rest_speed 0: exact events only), in the discrete method and
    in pymunk. Sleeping must not freeze it: the bottom two once fell asleep at the first
    instant, before the top ball's weight reached them, and the pyramid stood for ever
    (leaning.yields)."""
    positions = [[4.5, 0.5], [5.5, 0.5], [5.0, 0.5 + math.sqrt(3) / 2]]
    world, traj = ccd(positions, restitution=0.3)
    exact = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=3.0, method="ccd", rest_speed=0.0))
    end, reference = traj.positions[-1], exact.positions[-1]
    assert end[2, 1] == pytest.approx(0.5, abs=1e-9)                     # the top ball is on the floor
    assert reference[2, 1] == pytest.approx(0.5, abs=1e-9)
    assert np.abs(end[:2, 0] - reference[:2, 0]).max() < 0.1 * 0.5      # the bottom two where they slid to
    assert end[0, 0] < 2.0 and end[1, 0] > 8.0
    assert largest_overlap(traj) < 1e-9


@pytest.mark.parametrize("offset", [0.05, 0.3, 0.6])
def test_a_ball_leaning_on_another_pushes_it_aside_as_without_sleeping(offset):
    """A ball on top of another (radius 0.5), its centre `offset` to the side: it slides off and
    pushes the lower one the other way along the frictionless floor. With sleeping on, both end where they end with it off, within a tenth of a radius; the
    lower one once fell asleep at once and stayed put, and nearly balanced (0.05) the upper one
    stayed on top."""
    positions = [[5.0, 0.5], [5.0 + offset, 0.5 + math.sqrt(1.0 - offset * offset)]]
    world, traj = ccd(positions, restitution=0.3)
    exact = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=3.0, method="ccd", rest_speed=0.0))
    end, reference = traj.positions[-1], exact.positions[-1]
    assert np.allclose(end[:, 1], 0.5, atol=1e-9) and np.allclose(reference[:, 1], 0.5, atol=1e-9)   # both down
    assert np.abs(end[:, 0] - reference[:, 0]).max() < 0.1 * 0.5
    assert end[0, 0] < 4.0 and end[1, 0] > 6.0                          # pushed apart, not frozen in place
    assert largest_overlap(traj) < 1e-9


def test_a_row_held_between_the_walls_under_two_balls_stays_still():
    """A row of three balls wall to wall, two more in its cradles: the row's neighbours and the
    walls hold every push, so everything ends still, within a micro-bounce of where it began
    (the pyramid above's counterpart: a held row must not slide)."""
    r3 = math.sqrt(3) / 2
    positions = [[0.5, 0.5], [1.5, 0.5], [2.5, 0.5], [1.0, 0.5 + r3], [2.0, 0.5 + r3]]
    world, traj = ccd(positions, restitution=0.3, box=(0, 0, 3, 5))
    assert np.abs(traj.positions[-1] - traj.positions[0]).max() < 1e-3 * 0.5   # micro-bounces only
    assert traj.kinetic_energy()[-1] == 0.0


def test_only_a_world_where_bodies_may_rest_compiles_resting():
    """EventLoop.resting is None (the loop compiles no supports, sleeping nor carrying) exactly
    when no body can rest: no gravity and no rest speed."""
    from collisim.engine.ccd.events import start_event_loop

    def resting(gravity, rest_speed=None, restitution=0.5):
        return start_event_loop([[5.0, 5.0]], [[1.0, 0.0]], gravity, [0.5], [1.0], (0, 0, 10, 10), restitution,
                                None, 1.0, rest_speed=rest_speed).resting

    assert resting((0.0, 0.0)) is None
    assert resting((0.0, 0.0), restitution=1.0) is None
    assert resting((0.0, -G)) is True
    assert resting((0.0, -G), restitution=1.0) is True          # elastic, but may still rest on a floor
    assert resting((0.0, -G), rest_speed=0.0) is True
    assert resting((0.0, 0.0), rest_speed=0.1) is True           # a stated rest speed may put bodies to sleep
