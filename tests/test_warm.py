"""A first render compiles in two processes: the helper compiles the discrete step's far end
(engine/warm.py) for exactly the types the step hands those kernels, and ends with the render."""
import os
import tempfile

import numba
import numpy as np
import pytest

import collisim
from collisim import warm
from collisim.engine.discrete import DiscreteStepper
from collisim.engine.warm import compile_step_tail, step_tail_calls


@pytest.mark.parametrize("scene", ["particles_250", "polygons"])
def test_the_helper_compiles_each_kernel_for_the_types_the_step_hands_it(scene):
    scene = collisim.load_scene(scene)
    compile_step_tail(scene.world, scene.fps)
    kernels = [kernel for kernel, _ in step_tail_calls(scene.world, scene.fps)]
    compiled = [list(kernel.signatures) for kernel in kernels]
    stepper = DiscreteStepper(scene.world, scene.fps)
    frames, events = stepper.run(30)
    assert len(events.time) > 0   # bodies met: the step ran its solver and logged them
    # the run compiled none of them for other types: it used what the helper compiled
    assert [list(kernel.signatures) for kernel in kernels] == compiled
    assert np.isfinite(frames.positions).all()


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
