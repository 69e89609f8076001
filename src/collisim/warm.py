"""A render's first run, compiled by two processes: the render's own, and a helper started here.

On a fresh install (no discrete step in the cache folder yet: core/compiling.py) `collisim
render` starts this module as a second process (`start`), on the scene's world. While the render
compiles the discrete step from its start, the helper compiles it from its far end
(engine/warm.py) and then the disc and ring kernels of the drawing, and saves them into the
cache, where the render finds them and loads them instead of compiling them (docs/benchmarks.md,
the first run).

The helper writes nothing but kernels into the cache, prints nothing, and is ended with the
render (`stop`) whether the render ends, fails or is interrupted; left alone it ends by itself once
its kernels are compiled.
"""
from __future__ import annotations

import contextlib
import glob
import os
import pickle
import subprocess
import sys
import tempfile

import numba
import numpy as np

from .core import compiling
from .engine.discrete import run_frames
from .engine.warm import compile_far_end
from .render import splat


def _discrete_world(scene):
    """(world, fps, substeps, broadphase) of the first world in `scene` (itself, then its panels
    and chapters, depth first) that the discrete method runs, or None."""
    if scene.world is not None and scene.method == "discrete":
        return scene.world, scene.fps, scene.substeps, scene.broadphase
    for part in (*(panel.scene for panel in scene.panels), *scene.chapters):
        found = _discrete_world(part)
        if found is not None:
            return found
    return None


def kernels_cached() -> bool:
    """Whether the cache folder holds the discrete step already (for some world)."""
    folder = numba.config.CACHE_DIR   # (the step is called from Python: its copy's entries)
    step = f"discrete.{run_frames.__name__}{compiling.FROM_PYTHON}-*.nbi"
    return bool(folder) and bool(glob.glob(os.path.join(folder, "engine_*", step)))


def start(scene) -> subprocess.Popen | None:
    """The helper process, started on the scene's world when no step is in the cache yet, else
    None (a scene with no world the discrete method runs needs none either, nor a process whose
    saves into the cache do not take turns with other processes: core/compiling.py)."""
    if not compiling.saves_take_turns():
        return None   # no file locks, or numba's own folder
    found = None if kernels_cached() else _discrete_world(scene)
    if found is None:
        return None
    handle, path = tempfile.mkstemp(prefix="collisim-warm-", suffix=".pickle")
    with os.fdopen(handle, "wb") as file:
        pickle.dump(found, file)
    helper = subprocess.Popen([sys.executable, "-m", "collisim.warm", path], stdin=subprocess.DEVNULL,
                              stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    helper.world_file = path   # the helper removes it once read; stop() if it never got there
    return helper


def stop(helper: subprocess.Popen | None) -> None:
    """End the helper if it is still compiling (what it saved stays: numba writes each entry
    whole)."""
    if helper is None:
        return
    if helper.poll() is None:
        helper.terminate()
        helper.wait()
    with contextlib.suppress(FileNotFoundError):
        os.remove(helper.world_file)


def compile_drawing() -> None:
    """Compile the disc and ring kernels as a frame draws them: a disc and a ring on a BGR frame."""
    canvas = np.zeros((8, 8, 3), np.uint8)
    centre, colour = np.array([[4.0, 4.0]]), np.array([200.0, 100.0, 50.0])
    splat.draw_discs(canvas, centre, np.array([2.0]), colour)
    splat.draw_annuli(canvas, centre, np.array([2.0]), 1.0, colour, (0, 0, 8, 8))


def main(path: str) -> None:
    with open(path, "rb") as file:
        world, fps, substeps, broadphase = pickle.load(file)
    os.remove(path)
    compile_far_end(world, fps, substeps, broadphase)
    compile_drawing()


if __name__ == "__main__":
    main(sys.argv[1])
