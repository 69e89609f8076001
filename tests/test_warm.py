"""A first render compiles in two processes: the helper, handed every world of the scene, compiles
the discrete step's far end (engine/warm.py) for exactly the types the step hands those kernels,
and ends with the render."""
import os
import pickle
import tempfile

import numba
import numpy as np
import pytest
from numba.core import event

import collisim
from collisim import warm
from collisim.engine.discrete import DiscreteStepper
from collisim.engine.warm import compile_far_end, far_end_calls
from test_scenes import SCENES, worlds


def far_end_compiles(name: str) -> tuple:
    """(kernels the helper compiles, events the step logged, compiles the helper then made) for a
    shipped scene, after the step has run its world in this process."""
    scene = collisim.load_scene(name)
    frames, events = DiscreteStepper(scene.world, scene.fps).run(60)
    calls = far_end_calls(scene.world, scene.fps)
    with event.install_recorder("numba:compile") as recorded:
        compile_far_end(scene.world, scene.fps)
    return len(calls), len(events.time), sum(ev.is_start for _, ev in recorded.buffer)


def test_the_helper_compiles_each_kernel_for_the_types_the_step_hands_it():
    # The step's run compiled (or loaded) every kernel it calls, for the types it hands them,
    # into the cache folder: a helper that asks for any other type compiles it again here.
    # particles_250: a gas; teacher_drop: a world that may sleep, under gravity; bounding_volumes:
    # polygons, whose flight, fast pairs and bounding-volume funnel the helper compiles too
    (gas_helped, gas_logged, gas_again), (sleeping_helped, sleeping_logged, sleeping_again) = (
        far_end_compiles("particles_250"), far_end_compiles("teacher_drop"))
    polygons_helped, _, polygons_again = far_end_compiles("bounding_volumes")
    assert sleeping_helped == gas_helped + 5   # the sleepers' kernels
    assert polygons_helped >= gas_helped + 3
    assert gas_logged > 0 and sleeping_logged > 0   # bodies met: the step ran its contacts
    assert gas_again == 0 and sleeping_again == 0 and polygons_again == 0


def test_the_helper_starts_on_a_first_run_and_ends_with_the_render_leaving_no_file(tmp_path, monkeypatch):
    cache, temporary = tmp_path / "kernels", tmp_path / "tmp"
    cache.mkdir()
    temporary.mkdir()
    monkeypatch.setattr(numba.config, "CACHE_DIR", str(cache))   # no step compiled yet: a first run
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(cache))              # and the helper's cache too
    monkeypatch.setattr(tempfile, "tempdir", str(temporary))
    helper = warm.start(collisim.load_scene("particles_250"))
    assert helper is not None and helper.poll() is None and len(os.listdir(temporary)) == 1   # its world
    warm.stop(helper)   # as the render does when it ends, fails or is interrupted
    assert helper.poll() is not None and os.listdir(temporary) == []


def test_no_helper_starts_once_the_step_is_in_the_cache():
    # a run of the discrete step leaves it in this process's cache folder: a render after it
    # is no first run, and starts no second process
    scene = collisim.load_scene("particles_250")
    collisim.simulate(scene.replace(seconds=1.0 / scene.fps))
    assert warm.kernels_cached()
    assert warm.start(scene) is None


@pytest.mark.parametrize("name", SCENES)
def test_the_helper_is_handed_the_worlds_of_a_shipped_scene_intact(name):
    # the render pickles the helper's work: a world that did not survive it would stop the
    # render on a first run, or have the helper compile another world's step
    scene = collisim.load_scene(name)
    work = pickle.loads(pickle.dumps(warm.helper_work(*warm.steps_of(scene))))
    held = worlds(scene)
    for _, (method, world, *_) in work:
        assert any(np.array_equal(world.positions, other.positions) and np.array_equal(world.radii, other.radii)
                   and np.array_equal(world.shapes, other.shapes) and np.array_equal(world.box, other.box) and
                   len(world.level_segments) == len(other.level_segments) for other in held)
    # every step the scene runs, by method and broad phase
    first, later = warm.steps_of(scene)
    assert len(first + later) == len(held)
    assert {(step[0], step[4]) for _, step in work} == {(step[0], step[4]) for step in first + later}


def test_the_helpers_ray_query_is_the_one_a_scene_casts_from_a_recorded_frame():
    # raycast's overlay casts its sensor's rays at each frame's recorded positions and angles;
    # the helper casts one ray at the world's own: the same types, so the render loads its kernels
    scene = collisim.load_scene("raycast")
    frame = collisim.simulate(scene.replace(seconds=2.0 / scene.fps))
    origins, directions = np.array([[16.0, 9.0], [16.0, 9.0]]), np.array([[1.0, 0.0], [0.0, 1.0]])
    hits = collisim.raycast_many(scene.world, origins, directions, 40.0, positions=frame.positions[-1],
                                 angles=frame.angles[-1])
    assert hits.distance.shape == (2,)
    with event.install_recorder("numba:compile") as recorded:
        warm.compile_rays(scene.world)
    assert sum(ev.is_start for _, ev in recorded.buffer) == 0
