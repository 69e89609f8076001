"""One discrete step for every broad phase and block size: the same bytes, events included; its
profile accounts for the step's time; the shape-pair table is what the step dispatches."""
import time

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import collisim
from collisim.broadphase import NAMES
from collisim.engine import concatenate, stream
from collisim.engine.discrete import DiscreteStepper
from collisim.engine.eventlog import append, in_canonical_order, into_canonical_order, new_log
from collisim.model.trajectory import Events
from collisim.engine.profile import PHASES
from collisim.analysis.bench.segments import segment_gas
from collisim.gas import lattice_gas
from collisim.core.kinds import CIRCLE
from collisim.narrowphase.registry import SHAPE_PAIRS, contact, touching

EVENT_FIELDS = ("time", "kind", "i", "j", "impulse", "point")


def segments_scene(seconds=2.0):
    """A gas among 40 random thin segments, some crossing each other, under gravity."""
    world = segment_gas(200, 40, seed=11, length=3.0).copy(gravity=(0, -2.0), restitution=0.9)
    return collisim.Scene(world=world, fps=60, seconds=seconds)


@pytest.fixture(scope="module", params=["particles_250", "segments"])
def scene(request):
    if request.param == "segments":
        return segments_scene()
    return collisim.load_scene("particles_250").replace(seconds=2.0)


def assert_same_run(a, b):
    for name in ("positions", "velocities", "angles", "wall_collisions", "pair_collisions", "segment_collisions"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert len(a.events) == len(b.events)
    for name in EVENT_FIELDS:
        np.testing.assert_array_equal(getattr(a.events, name), getattr(b.events, name), err_msg=name)


def test_every_broad_phase_gives_the_same_positions_velocities_and_events(scene):
    """Among segments only the grid, which a gas chooses, is run against brute force: a broad
    phase sees the bodies' boxes alone, the segments are found in their own index whichever
    broad phase runs, and each broad phase with segments compiles a step of its own."""
    names = ("brute", "grid") if len(scene.world.segments) else NAMES
    runs = {name: collisim.simulate(scene.replace(broadphase=name)) for name in names}
    reference = runs["brute"]
    assert reference.pair_collisions.sum() > 50
    if len(scene.world.segments):
        assert reference.segment_collisions.sum() > 20
    for name, run in runs.items():
        assert_same_run(run, reference)


@pytest.mark.parametrize("block", [1, 7])
def test_streaming_in_blocks_of_any_size_gives_the_same_bytes(scene, block):
    whole = collisim.simulate(scene.replace(broadphase="grid"))
    streamed = concatenate(list(stream(scene.replace(broadphase="grid"), block=block)))
    assert_same_run(streamed, whole)


def test_events_agree_with_the_per_frame_counts(scene):
    traj = collisim.simulate(scene)
    frame_of_event = np.rint(traj.events.time * scene.fps).astype(int)
    for kind, counts in ((0, traj.wall_collisions), (1, traj.pair_collisions), (2, traj.segment_collisions)):
        per_frame = np.bincount(frame_of_event[traj.events.kind == kind], minlength=len(counts))
        if kind == 0:   # several bounces off one wall in one step are one event
            assert np.all(per_frame <= counts)
        else:
            np.testing.assert_array_equal(per_frame, counts)


def test_the_profile_accounts_for_the_steps_wall_time():
    scene = collisim.load_scene("particles_250")
    stepper = DiscreteStepper(scene.world, scene.fps, 1, "grid")
    stepper.run(2)   # compile or load outside the measurement
    stepper.profile.seconds.clear()
    shares, others = [], []
    for _ in range(3):    # the best of three: a shared machine may pause the process
        stepper.profile.seconds.clear()
        start = time.perf_counter()
        stepper.run(600)
        wall = time.perf_counter() - start
        phases = stepper.profile.seconds
        assert set(PHASES) <= set(phases)
        shares.append(sum(phases.values()) / wall)
        others.append(phases["other"] / sum(phases.values()))
    assert max(shares) == pytest.approx(1.0, abs=0.1)
    assert min(others) < 0.1   # the phases cover the compiled loop


def test_every_shape_pair_of_the_table_is_dispatched():
    positions = np.array([[0.0, 0.0], [1.5, 0.0], [5.0, 0.0]])
    radii = np.array([1.0, 0.6, 0.5])
    shapes = np.full(3, CIRCLE, np.int8)
    for (kind_a, kind_b), (touch, describe) in SHAPE_PAIRS.items():
        shapes[:] = kind_a
        shapes[1:] = kind_b
        for i, j in ((0, 1), (0, 2)):
            assert touching(shapes, positions, radii, i, j) == touch(positions, radii, i, j)
            assert contact(shapes, positions, radii, i, j) == describe(positions, radii, i, j)


def test_contacts_of_a_state_have_normals_depths_and_points():
    world = collisim.World([[1.0, 1.0], [3.0, 1.0], [5.0, 5.0]], radii=[1.0, 0.75, 0.5], box=(-2, -2, 8, 8))
    assert len(collisim.contacts(world)["pairs"]) == 0
    found = collisim.contacts(world, positions=[[1.0, 1.0], [2.5, 1.0], [5.0, 5.0]])
    np.testing.assert_array_equal(found["pairs"], [[0, 1]])
    np.testing.assert_allclose(found["normals"], [[1.0, 0.0]])
    np.testing.assert_allclose(found["depths"], [0.25])
    np.testing.assert_allclose(found["points"], [[1.875, 1.0]])   # midway between the two surfaces


def test_bodies_carry_angles_that_turn_at_their_angular_velocity():
    world = collisim.World([[2.0, 2.0], [6.0, 2.0]], radii=0.5, angles=[0.0, 1.0], angular_velocities=[2.0, -1.0],
                           box=(0, 0, 8, 4))
    for method in ("discrete", "ccd"):
        traj = collisim.simulate(collisim.Scene(world=world, fps=30, seconds=1.0, method=method))
        np.testing.assert_allclose(traj.angles[-1], [2.0, 0.0], atol=1e-12)
        np.testing.assert_array_equal(traj.angular_velocities[-1], [2.0, -1.0])
    np.testing.assert_allclose(world.inertias, 0.5 * world.masses * 0.25)


def test_auto_picks_a_broad_phase_by_what_the_world_holds_and_says_which():
    from collisim.broadphase.registry import choose
    few = collisim.World([[1.0, 1.0], [3.0, 1.0]], radii=0.5)
    gas = collisim.load_scene("particles_250").world
    big = lattice_gas(300, box=(0, 0, 60, 60), speed=1.0, seed=2)
    radii = big[2].copy()
    radii[0] = 9 * np.median(radii)   # one body far larger than the rest
    positions = big[0].copy()
    positions[0] = [30.0, 30.0]
    keep = (np.hypot(*(positions - positions[0]).T) > radii[0] + radii) | (np.arange(300) == 0)
    mixed = collisim.World(positions[keep], radii=radii[keep], box=(0, 0, 60, 60))
    assert (choose(few), choose(gas), choose(mixed)) == ("brute", "grid", "bvh")
    scene = collisim.Scene(world=gas, seconds=0.25)
    assert scene.broadphase == "auto"
    traj = collisim.simulate(scene)
    assert traj.broadphase == "grid (auto)"
    assert_same_run(traj, collisim.simulate(scene.replace(broadphase="sweep_prune")))


def test_the_event_log_is_capped_with_one_note_and_the_counts_stay_complete():
    scene = collisim.load_scene("particles_250").replace(seconds=1.0)
    full = collisim.simulate(scene)
    assert len(full.events) > 100
    with pytest.warns(UserWarning, match="only the first 100 collision events are kept") as caught:
        capped = collisim.simulate(scene, max_events=100)
    assert len(caught) == 1 and len(capped.events) == 100
    for name in ("time", "kind", "i", "j"):
        np.testing.assert_array_equal(getattr(capped.events, name), getattr(full.events, name)[:100])
    np.testing.assert_array_equal(capped.collisions, full.collisions)
    none = collisim.simulate(scene, max_events=0)
    assert len(none.events) == 0 and none.collisions.sum() == full.collisions.sum()


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 5), st.integers(0, 4), st.integers(0, 40), st.integers(-1, 44)),
                max_size=60), st.booleans(), st.sampled_from([1, 10 ** 6]))
def test_the_step_sorts_its_log_as_lexsort_orders_the_events(rows, in_time_order, scale):
    # the step sorts its block's log into (time, kind, i, j) order where it logged it, ties in
    # the order logged (engine/eventlog.py); a log whose times go back is left for Python to sort
    if in_time_order:   # as a block's log is: step after step
        rows = sorted(rows, key=lambda row: row[0])
    log = new_log(max(len(rows), 1))
    for number, (time_, kind, i, j) in enumerate(rows):
        append(log, time_ / 8.0, kind, i * scale, j * scale if j >= 0 else j, float(number), number, -number)
    k = len(rows)
    before = [np.array(field[:k]) for field in log[:6]]
    expected = np.lexsort((before[3], before[2], before[1], before[0]))
    times_go_back = bool(np.any(np.diff(before[0]) < 0))
    assert into_canonical_order(log) == (not times_go_back)
    for field, was in zip(log[:6], before):
        assert np.array_equal(field[:k], was if times_go_back else was[expected])


@settings(max_examples=200, deadline=None)
@given(st.lists(st.tuples(st.integers(0, 3), st.integers(0, 4), st.integers(0, 3), st.integers(-1, 3)),
                max_size=12))
def test_the_step_tells_canonical_order_as_events_do(rows):
    # the step says whether its log is in (time, kind, i, j) order, and its events are then not
    # sorted again (engine/eventlog.py): with ties on every key, as a world asleep logs them
    log = new_log(max(len(rows), 1))
    for time_, kind, i, j in rows:
        append(log, time_ / 8.0, kind, i, j, 1.0, 0.0, 0.0)
    k = len(rows)
    events = Events(log.time[:k], log.kind[:k], log.i[:k], log.j[:k], log.impulse[:k], log.point[:k])
    assert in_canonical_order(log) == events.in_order()
