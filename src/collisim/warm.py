"""A render's first run, compiled by two processes: the render's own, and a helper started here.

On a fresh install (a method the scene runs has no step in the cache folder yet:
core/compiling.py) `collisim render` starts this module as a second process (`start`), on the
steps of the scene's worlds (`steps_of`). It works on those of the first frame (every panel's,
the first chapter's) from the other end than the render (`helper_work`):

* first the steps of the other method than the first world's: a scene of both methods
  (collision_map) compiles ccd's event loop beside the render's discrete step instead of after
  it, the two sharing almost no kernel;
* then the first world's discrete step from its far end (engine/warm.py), while the render
  compiles it from its start (before it, a world with polygons' first funnel, which the render
  counts from Python), and the disc and ring kernels of the drawing;
* then the first method's other broad phases, last first;

and then the later chapters' steps, in the order the render reaches them; and last the ray query
for a world, which the render compiles for Python, after its step, when a scene's overlay casts
rays (the raycast scene).

It saves what it compiles into the cache, where the render finds it and loads it instead of
compiling it (docs/benchmarks.md, the first run). The helper writes nothing but kernels into the
cache, prints nothing, and is ended with the render (`stop`) whether the render ends, fails or is
interrupted; left alone it ends by itself once its kernels are compiled.
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
from .engine.ccd.events import _run as ccd_run
from .engine.ccd.stepper import CCDStepper
from .engine.discrete import DiscreteStepper, run_frames
from .engine.hierarchy import world_counts
from .engine.warm import compile_far_end
from .queries.rays import raycast_many
from .render import splat

STEPS = {"discrete": ("engine_*", run_frames), "ccd": ("ccd_*", ccd_run)}   # cache subfolder, step kernel


def steps_of(scene) -> tuple:
    """What builds the step of each world `scene` runs, as (first, later): the steps its first
    frame needs (all its panels', and of its chapters the first's), then the later chapters'
    steps, each list in the order the render compiles them (panels, then chapters, depth first).
    A step: (method, world, fps, substeps, broadphase, rest_speed, tc)."""
    if scene.world is not None:
        return [(scene.method, scene.world, scene.fps, scene.substeps, scene.broadphase, scene.rest_speed,
                 scene.tc)], []
    first, later = [], []
    for panel in scene.panels:
        panel_first, panel_later = steps_of(panel.scene)
        first, later = first + panel_first, later + panel_later
    for number, chapter in enumerate(scene.chapters):
        chapter_first, chapter_later = steps_of(chapter)
        if number == 0:
            first, later = first + chapter_first, later + chapter_later
        else:
            later = later + chapter_first + chapter_later
    return first, later


def helper_work(first: list, later: list) -> list:
    """The helper's work on a scene's steps (steps_of), in order (the module docstring):
    ("step", step) compiles a whole step, ("far end", step) the discrete step's far end and the
    drawing. The first frame's steps come first; the later chapters' follow, in the order the
    render reaches them."""
    if not first:
        return [("step", step) for step in later]
    head, rest = first[0], first[1:]
    other = [("step", step) for step in rest if step[0] != head[0]]
    far_end = [("far end", head)] if head[0] == "discrete" else []
    # the same method's other broad phases, each where the render first meets it, last first
    # (broadphase_six meets sweep and prune twice: the helper takes it last, not first)
    met, same = {(head[0], head[4])}, []
    for step in rest:
        if step[0] == head[0] and (step[0], step[4]) not in met:
            met.add((step[0], step[4]))
            same.insert(0, ("step", step))
    return other + far_end + same + [("step", step) for step in later]


def kernels_cached(methods=("discrete",)) -> bool:
    """Whether the cache folder holds the step of every one of `methods` already (for some world)."""
    folder = numba.config.CACHE_DIR   # (a step is called from Python: its copy's entries)
    if not folder:
        return False
    for method in methods:
        subfolder, step = STEPS[method]
        name = f"{step.__module__.rsplit('.', 1)[-1]}.{step.__name__}{compiling.FROM_PYTHON}-*.nbi"
        if not glob.glob(os.path.join(folder, subfolder, name)):
            return False
    return True


def start(scene) -> subprocess.Popen | None:
    """The helper process, started on the scene's steps when a method it runs has no step in the
    cache yet, else None (nor for a process whose saves into the cache do not take turns with
    other processes: core/compiling.py)."""
    if not compiling.saves_take_turns():
        return None   # no file locks, or numba's own folder
    first, later = steps_of(scene)
    if kernels_cached({step[0] for step in first + later}):
        return None
    handle, path = tempfile.mkstemp(prefix="collisim-warm-", suffix=".pickle")
    try:
        with os.fdopen(handle, "wb") as file:
            pickle.dump(helper_work(first, later), file)
    except (pickle.PicklingError, TypeError, AttributeError):   # a world of a user's own making: no help
        os.remove(path)
        return None
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


def compile_step(method, world, fps, substeps, broadphase, rest_speed, tc) -> None:
    """Compile (or load) a step as the engine builds it (engine/simulate.METHODS): ccd's loop
    compiles as it starts, the discrete step at its first frame."""
    if method == "ccd":
        CCDStepper(world, fps, 1, rest_speed=rest_speed, tc=tc)
    else:
        DiscreteStepper(world, fps, substeps, broadphase, rest_speed=rest_speed).run(1)


def compile_rays(world) -> None:
    """Compile the ray query (queries/rays.py) for the world's bodies, as a scene's overlay casts
    its rays from Python once a frame's step is done: one ray from the first body's centre."""
    if world.n:
        raycast_many(world, world.positions[:1], np.array([[1.0, 0.0]]), 1.0)


def main(path: str) -> None:
    with open(path, "rb") as file:
        work = pickle.load(file)
    os.remove(path)
    for what, (method, world, fps, substeps, broadphase, rest_speed, tc) in work:
        if what == "far end":
            world_counts(world)   # a world with polygons: its first frame's funnel, from Python
            compile_far_end(world, fps, substeps, broadphase, rest_speed)
            compile_drawing()
        else:
            compile_step(method, world, fps, substeps, broadphase, rest_speed, tc)
    if work:   # last, what the render compiles for Python only if the scene casts rays
        _, (_, world, *_) = work[0]
        compile_rays(world)


if __name__ == "__main__":
    main(sys.argv[1])
