"""The engine simulates one block ahead on a thread of its own while the player draws
(engine/ahead.py): the same blocks in the same order, errors where they happened, at most one
block ahead, and no thread left behind."""
import gc
import threading
import time

import numpy as np
import pytest

import collisim
from collisim.engine.ahead import Ahead
from collisim.engine.simulate import METHODS
from collisim.gas import lattice_gas
from test_player import decoded_frames

SIZE = (320, 180)


def engine_threads() -> int:
    return sum(thread.name == "collisim-engine" and thread.is_alive() for thread in threading.enumerate())


def wait_until(condition, seconds: float = 10.0) -> bool:
    end = time.monotonic() + seconds
    while not condition():
        if time.monotonic() > end:
            return False
        time.sleep(0.01)
    return True


class Counted:
    """An iterator of 0 .. n - 1 that counts the items made, can fail at one, and notes its closing."""

    def __init__(self, n: int, fail_at: int | None = None):
        self.n, self.fail_at, self.made, self.closed = n, fail_at, 0, False

    def __iter__(self):
        try:
            for k in range(self.n):
                if k == self.fail_at:
                    raise ValueError(f"block {k} failed")
                self.made += 1
                yield k
        finally:
            self.closed = True


@pytest.fixture(autouse=True)
def no_engine_thread_left():
    yield
    gc.collect()
    assert wait_until(lambda: engine_threads() == 0), "an engine thread outlived its iterator"


def test_the_blocks_come_in_order_and_the_iterator_ends():
    ahead = Ahead(iter(Counted(7)))
    assert list(ahead) == list(range(7))
    with pytest.raises(StopIteration):
        next(ahead)


def test_an_empty_stream_ends_at_once():
    assert list(Ahead(iter(()))) == []


def test_at_most_one_block_is_computed_ahead_of_the_one_in_use():
    source = Counted(10)
    ahead = Ahead(iter(source))
    for k in range(4):
        assert next(ahead) == k
        assert wait_until(lambda: source.made == k + 2)
        time.sleep(0.05)
        assert source.made == k + 2   # block k in use, k + 1 waiting; k + 2 not begun
    ahead.close()


def test_an_error_is_raised_where_its_block_would_have_come():
    ahead = Ahead(iter(Counted(9, fail_at=3)))
    assert [next(ahead) for _ in range(3)] == [0, 1, 2]
    with pytest.raises(ValueError, match="block 3 failed"):
        next(ahead)
    with pytest.raises(StopIteration):
        next(ahead)


def test_closing_stops_the_worker_and_closes_the_stream():
    source = Counted(1000)
    ahead = Ahead(iter(source))
    assert next(ahead) == 0
    ahead.close()
    assert wait_until(lambda: source.closed and engine_threads() == 0)
    assert source.made <= 3
    with pytest.raises(StopIteration):
        next(ahead)


def test_dropping_the_iterator_stops_the_worker():
    source = Counted(1000)
    ahead = Ahead(iter(source))
    next(ahead)
    del ahead
    gc.collect()
    assert wait_until(lambda: source.closed and engine_threads() == 0)


def test_a_render_of_many_blocks_shows_the_frames_of_the_whole_trajectory(tmp_path):
    scene = collisim.load_scene("particles_250").replace(seconds=2.2)   # 132 frames: three blocks of 64, the last short
    streamed = collisim.render(scene, tmp_path / "streamed.mp4", SIZE)
    whole = collisim.render(collisim.simulate(scene), tmp_path / "whole.mp4", SIZE, settings=scene.render)
    a, b = decoded_frames(streamed), decoded_frames(whole)
    assert len(a) == len(b) == collisim.pipeline.plan(scene, SIZE).frames
    for x, y in zip(a, b):
        np.testing.assert_array_equal(x, y)


@pytest.mark.parametrize("method", ["discrete", "ccd"])
def test_the_compiled_block_lets_other_threads_run(method):
    """Without the GIL released, the counting thread would stand still for the whole block."""
    box = (0.0, 0.0, 200.0, 200.0)
    positions, velocities, radii = lattice_gas(20_000, box=box, speed=3.0, seed=1)
    world = collisim.World(positions=positions, velocities=velocities, radii=radii, box=box)
    scene = collisim.Scene(world=world, fps=60, seconds=1.0, method=method, broadphase="grid")
    stepper = METHODS[method](scene)
    stepper.run(1)   # compiled before the count
    counts, running = [], threading.Event()

    def count():
        running.set()
        while running.is_set():
            counts.append(time.perf_counter())
            time.sleep(0)

    counter = threading.Thread(target=count)
    counter.start()
    running.wait()
    start = time.perf_counter()
    stepper.run(32)
    end = time.perf_counter()
    running.clear()
    counter.join()
    during = sum(start < t < end for t in counts)
    assert during > 100, f"{during} counts in a block of {1e3 * (end - start):.0f} ms"
