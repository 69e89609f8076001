"""How simulate keeps the frames: float64, float32 or positions only, written into one
trajectory allocated up front (engine/simulate.py: Recorder)."""
from types import SimpleNamespace

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

import collisim
from collisim.engine.simulate import Recorder, block_frames, concatenate, stream
from collisim.model.trajectory import load_trajectory


@pytest.fixture(scope="module")
def scene():
    return collisim.load_scene("particles_250").replace(seconds=1.5)


@pytest.fixture(scope="module")
def exact(scene):
    return collisim.simulate(scene)


def test_float32_keeps_the_float64_run_rounded(scene, exact):
    run = collisim.simulate(scene, storage="float32")
    for name in ("positions", "velocities", "angles", "angular_velocities"):
        kept = getattr(run, name)
        assert kept.dtype == np.float32 and kept.shape == getattr(exact, name).shape
        np.testing.assert_array_equal(kept, getattr(exact, name).astype(np.float32), err_msg=name)
    np.testing.assert_array_equal(run.pair_collisions, exact.pair_collisions)
    np.testing.assert_array_equal(run.events.impulse, exact.events.impulse)  # the engine ran in float64
    assert run.storage == "float32"


def test_positions_storage_keeps_no_velocities(scene, exact):
    run = collisim.simulate(scene, storage="positions")
    np.testing.assert_array_equal(run.positions, exact.positions.astype(np.float32))
    assert run.velocities.shape == exact.velocities.shape and np.isnan(run.velocities).all()
    assert not run.velocities.flags.writeable and run.velocities.strides[0] == 0  # no memory per frame
    with pytest.raises(ValueError, match="storage='positions'"):
        run.kinetic_energy()


def test_velocity_arrows_of_a_positions_only_trajectory_are_refused_before_anything_is_drawn(scene, tmp_path):
    run = collisim.simulate(scene, storage="positions")
    with pytest.raises(ValueError, match="velocity arrows need velocities.*storage='positions'"):
        collisim.render(run, tmp_path / "arrows.mp4", (160, 90), settings=collisim.RenderSettings(arrows=True))
    assert list(tmp_path.iterdir()) == []
    collisim.render(run, tmp_path / "plain.mp4", (160, 90))   # without arrows it plays


def test_bodies_that_never_turn_store_their_angles_once(exact):
    assert np.all(exact.world.angular_velocities == 0)
    assert exact.angles.strides[0] == 0 and exact.angles.shape == (exact.frames + 1, exact.world.n)
    np.testing.assert_array_equal(exact.angles[-1], exact.world.angles)


def test_blocks_shrink_for_very_many_bodies_and_give_the_same_bytes(scene, exact):
    assert block_frames(scene) == 64
    million = SimpleNamespace(world=SimpleNamespace(n=1_000_000), method="discrete")
    assert block_frames(million) == 1  # 32 MB a frame
    assert block_frames(SimpleNamespace(world=million.world, method="ccd")) == 64
    one_by_one = concatenate(list(stream(scene, block=1)))
    for name in ("positions", "velocities", "candidates", "pair_collisions"):
        np.testing.assert_array_equal(getattr(one_by_one, name), getattr(exact, name), err_msg=name)


@pytest.mark.parametrize("method", ["discrete", "ccd"])
def test_later_blocks_are_written_straight_into_the_trajectory(scene, exact, method):
    run_scene = scene.replace(method=method)
    whole = exact if method == "discrete" else collisim.simulate(run_scene)
    recorder = Recorder(run_scene.frames + 1)
    written_in_place = 0
    for block in stream(run_scene, block=16, into=recorder.views):
        if recorder.filled:   # every block after the first: the trajectory's own rows
            for name in ("positions", "velocities"):
                assert np.shares_memory(getattr(block, name), recorder.arrays[name]), name
            written_in_place += 1
        recorder.add(block)
    assert written_in_place == 5   # 91 samples in blocks of 16
    run = recorder.trajectory()
    for name in ("positions", "velocities", "pair_collisions", "wall_collisions"):
        np.testing.assert_array_equal(getattr(run, name), getattr(whole, name), err_msg=name)
    assert Recorder(run_scene.frames + 1, "float32").views(16, 16) is None   # converted: copied in


def test_a_first_block_of_one_sample_still_lets_the_engine_write_in_place(scene, exact):
    recorder = Recorder(scene.frames + 1)
    blocks = stream(scene, block=1, into=recorder.views)
    recorder.add(next(blocks))   # the t = 0 sample alone (a million bodies: one frame a block)
    for block in blocks:
        assert np.shares_memory(block.positions, recorder.arrays["positions"])
        recorder.add(block)
    np.testing.assert_array_equal(recorder.trajectory().positions, exact.positions)
    np.testing.assert_array_equal(recorder.trajectory().velocities, exact.velocities)


def test_storage_survives_a_save(scene, tmp_path):
    run = collisim.simulate(scene.replace(seconds=0.2), storage="float32")
    loaded = load_trajectory(run.save(tmp_path / "run.npz"))
    assert loaded.storage == "float32" and loaded.positions.dtype == np.float32


def test_unknown_storage(scene):
    with pytest.raises(ValueError, match="^unknown storage 'float16'; choose one of: float64, float32, positions$"):
        collisim.simulate(scene, storage="float16")


def test_the_memory_benchmark_counts_a_repeated_row_once(exact):
    from collisim.analysis.bench.memory import held_bytes

    held = held_bytes(exact)
    samples, n = exact.positions.shape[:2]
    per_frame = exact.times.nbytes + 3 * exact.wall_collisions.nbytes + exact.candidates.nbytes + samples  # + bool
    assert held["frames"] == 2 * samples * n * 2 * 8 + 2 * n * 8 + per_frame  # angles: one row each
    assert held["events"] == len(exact.events) * (8 + 1 + 8 + 8 + 8 + 16)


def test_a_grown_log_keeps_its_events_and_copies_only_what_it_holds():
    from collisim.core.arrays import grown
    from collisim.engine.eventlog import append, new_log, with_room
    log = new_log(4)
    for k in range(3):
        append(log, 0.5 * k, 1, k, k + 1, 2.0 * k, k, -k)
    bigger = with_room(log, 100)
    assert bigger.time.shape[0] >= 103 and bigger.size[0] == 3
    assert bigger.time[:3].tolist() == [0.0, 0.5, 1.0] and bigger.j[:3].tolist() == [1, 2, 3]
    assert bigger.point[:3].tolist() == [[0.0, 0.0], [1.0, -1.0], [2.0, -2.0]]
    assert np.shares_memory(with_room(bigger, 50).time, bigger.time)      # room left: the same arrays
    marked = np.arange(10.0)
    kept = grown(marked, 30, 4)
    assert kept.shape == (30,) and kept[:4].tolist() == [0.0, 1.0, 2.0, 3.0]
    assert grown(marked, 12).shape == (20,) and grown(marked, 12)[:10].tolist() == marked.tolist()
    assert grown(marked, 5) is marked


@pytest.mark.parametrize("shape", [(5,), (5, 2), (5, 3, 2), (0, 2)])
def test_copy_rows_copies_the_first_rows_and_leaves_the_rest(shape):
    from collisim.core.arrays import copy_rows
    source = np.random.default_rng(1).normal(size=shape)
    target = np.full((7,) + shape[1:], -1.0)
    count = min(3, shape[0])
    copy_rows(source, target, count)
    assert np.array_equal(target[:count], source[:count]) and np.all(target[count:] == -1.0)


@settings(max_examples=200, deadline=None)
@given(st.lists(st.integers(-3, 3) | st.integers(-2**63, 2**63 - 1), max_size=70), st.booleans())
def test_the_kernels_sort_is_numpys_stable_argsort(values, as_floats):
    # runs of equal keys, whose order a stable sort keeps (the warm start and the hold sort by
    # them, and their bytes must not depend on the sort), and keys across the whole int64 range
    from collisim.core.arrays import stable_order, stable_order_of_floats
    keys = np.array(values, np.int64)
    if as_floats:   # with -0.0 among them, which numpy takes as equal to 0.0
        keys = np.where(keys == 1, -0.0, keys / 3.0)
    order = stable_order_of_floats(keys) if as_floats else stable_order(keys)
    assert np.array_equal(order, np.argsort(keys, kind="stable"))


@settings(max_examples=200, deadline=None)
@given(st.integers(1, 300), st.integers(1, 40), st.integers(0, 2 ** 31), st.booleans(), st.sampled_from([5, 10 ** 6]))
def test_events_come_in_the_order_lexsort_gives(count, steps, seed, in_time_order, bodies):
    # the stable order by (time, kind, i, j), ties kept in the order logged, whichever way it is found
    rng = np.random.default_rng(seed)
    time = rng.integers(0, steps, count) / 60.0
    if in_time_order:   # as a block's log is: step after step
        time = np.sort(time)
    kind = rng.integers(0, 5, count).astype(np.int8)
    i = rng.integers(0, bodies, count)
    j = rng.integers(-1, bodies + 4, count)
    events = collisim.Events(time, kind, i, j, rng.random(count), rng.random((count, 2)))
    expected = events.take(np.lexsort((j, i, kind, time)))
    got = collisim.Events.concatenate([events])
    for name in ("time", "kind", "i", "j", "impulse", "point"):
        assert np.array_equal(getattr(got, name), getattr(expected, name))
