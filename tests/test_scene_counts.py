"""Numbers a tutorial scene puts on screen are the engine's, on every frame: each caption that
states a count is checked against the trajectory it is drawn from."""
import re

import numpy as np
import pytest

import collisim
from collisim.render.player import FrameState
from collisim.model.scenefile import available_scenes


@pytest.fixture(scope="module")
def six():
    """The scene file as a module, to call its caption functions."""
    import importlib.util
    spec = importlib.util.spec_from_file_location("broadphase_six_scene", available_scenes()["broadphase_six"])
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def states(trajectory):
    """A FrameState for every sample, as the player builds them."""
    for f in range(len(trajectory.times)):
        past = trajectory.events.take(trajectory.events.time <= trajectory.times[f] + 1e-12)
        yield FrameState(float(trajectory.times[f]), f, trajectory.positions[f], trajectory.velocities[f],
                         trajectory.angles[f], int(trajectory.candidates[f]), int(trajectory.pair_collisions[f]),
                         0, 0, past)


def numbers(text):
    return [int(n) for n in re.findall(r"\d+", text)]


def test_the_narrow_phase_caption_counts_what_the_engine_found_on_every_frame(six):
    panel = six.narrow_panel()
    trajectory = collisim.simulate(panel.scene)
    touched = 0
    for state in states(trajectory):
        found = numbers(six.narrow_caption(state))
        assert found == [trajectory.pair_collisions[state.sample], trajectory.candidates[state.sample]]
        assert len(six.touching_now(state)) == trajectory.pair_collisions[state.sample]
        touched += found[0]
    assert touched > 0   # the scene does show pairs touching


@pytest.mark.parametrize("method", ["brute", "sweep_prune", "grid", "kdtree", "bvh"])
def test_each_broad_phase_caption_counts_the_engines_candidates(six, method):
    trajectory = collisim.simulate(six.panel(method).scene)
    for state in states(trajectory):
        text = six.broad_caption(method, state, 15)
        assert trajectory.candidates[state.sample] in numbers(text)
        assert ("1 candidate pair " in text + " ") or "1 candidate pairs" not in text   # grammar


def test_tunneling_counts_each_missed_particle_once():
    """A particle that tunnelled through the barrier crosses it again every time it comes back;
    the counter counts particles, so it never exceeds the number of particles."""
    import importlib.util
    spec = importlib.util.spec_from_file_location("tunneling_scene", available_scenes()["tunneling"])
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    world = module.barrier_world()
    trajectory = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=8.0, broadphase="brute"))
    once = module.MissedOnce(module.barrier_crossings)
    every = 0
    total = 0
    frames = list(states(trajectory))
    for before, after in zip(frames, frames[1:]):
        total += once(before, after)
        every += int(module.barrier_crossings(before, after).sum())
    assert 0 < total <= world.n < every     # repeated crossings happen, and are not counted again
