"""The workloads a sweep can name: the accuracy benchmark's four, and `barrier` for tunnelling.

* slow_gas, dense_gas, fast_gas, gravity_bounce: collisim.analysis.bench.workloads (speeds in
  radii per frame at 60 fps, every radius 1).
* barrier(speed, phase, fps): one particle flying at a thin segment, the experiment of
  tests/test_tunneling.py one lane at a time. `speed` is its travel per frame in radii at the
  job's fps; `phase` in [0, 1] is where in a frame the contact falls. A discrete step sees the
  segment only if a frame lands while the particle overlaps it, a window of one radius out of
  `speed` radii travelled, so over evenly spread phases the particle crosses (missed_segments
  = 1) in a fraction max(0, 1 - 1/speed) of the jobs; ccd never crosses.

A sweep passes a generator only the parameters its signature takes (`n` reaches
gravity_bounce as `count`); parameters_of(name) says which.
"""
from __future__ import annotations

import inspect

from ...model.scene import Scene
from ...model.world import World
from ..bench.workloads import WORKLOADS as BENCH_WORKLOADS

BARRIER_RADIUS = 0.5
BARRIER_FRAMES = 8        # contact between frames 3 and 4, then room to fly on
LANE = 10.0               # half-height of the box; the segment spans half of it


def barrier(speed: float = 2.0, phase: float = 0.5, fps: float = 60.0) -> Scene:
    """One particle moving `speed` radii per frame at a thin vertical segment at x = 0, starting
    so that its contact would fall `phase` of a frame after the third frame."""
    travel = speed * BARRIER_RADIUS
    x0 = -BARRIER_RADIUS - 3.0 * travel - phase * travel
    world = World(positions=[[x0, 0.0]], velocities=[[travel * fps, 0.0]], radii=BARRIER_RADIUS,
                  box=(-1e5, -LANE, 1e5, LANE), segments=[[0.0, -LANE / 2, 0.0, LANE / 2]])
    return Scene(world=world, fps=fps, seconds=BARRIER_FRAMES / fps, method="discrete", broadphase="brute",
                 name="barrier", description=f"a particle at {speed:g} radii per frame against a thin segment")


WORKLOADS = {**BENCH_WORKLOADS, "barrier": barrier}
ALIASES = {"n": "count"}   # a sweep's name -> a generator's name for the same thing


def _argument(name: str, parameter: str):
    """The generator's keyword for a sweep parameter, or None if it takes none."""
    taken = inspect.signature(WORKLOADS[name]).parameters
    for keyword in (parameter, ALIASES.get(parameter)):
        if keyword in taken:
            return keyword
    return None


def takes(name: str, parameter: str) -> bool:
    """Whether workload `name` takes sweep parameter `parameter`."""
    return _argument(name, parameter) is not None


def make_workload(name: str, settings: dict) -> Scene:
    """The workload's scene, built with those of `settings` its generator takes."""
    if name not in WORKLOADS:
        raise ValueError(f"unknown workload '{name}'; choose from: {', '.join(WORKLOADS)}")
    arguments = {}
    for parameter, value in settings.items():
        keyword = _argument(name, parameter)
        if keyword is not None:
            arguments[keyword] = value
    return WORKLOADS[name](**arguments)
