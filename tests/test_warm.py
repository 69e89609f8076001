"""A first render compiles in two processes: the helper compiles the discrete step's far end
(engine/warm.py) for exactly the types the step hands those kernels, and ends with the render."""
import os
import subprocess
import sys
import tempfile

import numba
import pytest

import collisim
from collisim import warm

HELPER_THEN_RUN = """
import sys
from numba.core import event
import collisim
from collisim.engine.discrete import DiscreteStepper
from collisim.engine.warm import compile_far_end, far_end_calls

for name in sys.argv[1:]:
    scene = collisim.load_scene(name)
    helped = {kernel.function for kernel, _ in far_end_calls(scene.world, scene.fps)}
    compile_far_end(scene.world, scene.fps)
    with event.install_recorder("numba:compile") as recorded:
        frames, events = DiscreteStepper(scene.world, scene.fps).run(60)
    functions = [ev.data["dispatcher"].py_func for _, ev in recorded.buffer if ev.is_start]
    print(len(helped), len(events.time), len(functions), sum(f in helped for f in functions))
"""


@pytest.mark.slow
def test_the_helper_compiles_each_kernel_for_the_types_the_step_hands_it(tmp_path):
    # a fresh process with an empty kernel cache: what a run compiles is what the helper missed.
    # particles_250: a gas; teacher_drop: a world that may sleep, under gravity
    env = dict(os.environ, NUMBA_CACHE_DIR=str(tmp_path), COLLISIM_CACHE_DIR=str(tmp_path / "c"))
    result = subprocess.run([sys.executable, "-c", HELPER_THEN_RUN, "particles_250", "teacher_drop"], env=env,
                            capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stderr
    (gas_helped, *gas), (sleeping_helped, *sleeping) = [map(int, line.split()) for line in result.stdout.splitlines()]
    assert sleeping_helped == gas_helped + 5   # the sleepers' kernels
    for logged, compiled, compiled_again in (gas, sleeping):
        assert logged > 0 and compiled > 0   # bodies met, and the run compiled the rest of the step
        assert compiled_again == 0           # and none of the helper's kernels


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
