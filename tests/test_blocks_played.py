"""A panel draws the same pixels whether its trajectory streams in blocks of any size (a
million bodies stream one frame a block) or comes whole: flashes, explainers and counters that
look back in time see the same past."""
import hashlib

import numpy as np
import pytest

import collisim
from collisim.engine import stream
from collisim.pipeline import plan
from collisim.render.player import Chapter, PanelSource
from collisim.render.timeline import Timeline

SIZE = (320, 180)
SCENES = {"particles_250": 1.5, "two_bodies": 2.5, "single_bounce": 2.0, "raycast": 1.5}


def drawn(scene, blocks) -> list:
    """A digest of every video frame the panel draws from blocks() (an iterator of Trajectory)."""
    job = plan(scene, SIZE)
    source = PanelSource(blocks, scene.render, "", scene.frames, scene.fps)
    timeline = Timeline([Chapter([source], job.frames, scene.render.layout)], SIZE, job.fps)
    canvas = np.empty((SIZE[1], SIZE[0], 3), np.uint8)
    digests = []
    for frame in range(job.frames):
        timeline.draw(canvas, frame)
        digests.append(hashlib.sha256(canvas.tobytes()).hexdigest())
    timeline.close()
    return digests


@pytest.fixture(scope="module", params=sorted(SCENES))
def scene_and_whole(request):
    scene = collisim.load_scene(request.param).replace(seconds=SCENES[request.param])
    trajectory = collisim.simulate(scene)
    return scene, drawn(scene, lambda: iter([trajectory]))


@pytest.mark.parametrize("block", [1, 5])
def test_a_streamed_panel_draws_what_the_whole_trajectory_draws(scene_and_whole, block):
    scene, whole = scene_and_whole
    streamed = drawn(scene, lambda: stream(scene, block=block))
    assert len(streamed) == len(whole)
    differ = [k for k, (a, b) in enumerate(zip(streamed, whole)) if a != b]
    assert not differ, f"{len(differ)} of {len(whole)} frames differ, the first at video frame {differ[0]}"


@pytest.mark.parametrize("name", ["two_bodies", "raycast", "single_bounce"])
def test_a_scene_keeps_nothing_from_one_play_to_the_next(name):
    """What an explainer or overlay reads once (a moment, a velocity at the impact, a missile's
    hit) is kept for one play: playing the same scene object at another restitution first
    changes nothing."""
    seconds = SCENES[name]
    fresh = collisim.load_scene(name).replace(seconds=seconds)
    expected = drawn(fresh, lambda: stream(fresh))
    scene = collisim.load_scene(name).replace(seconds=seconds)
    other = scene.with_options(restitution=0.5)
    assert other.render is scene.render   # the same explainer and overlay objects
    drawn(other, lambda: stream(other))
    again = drawn(scene, lambda: stream(scene))
    differ = [k for k, (a, b) in enumerate(zip(again, expected)) if a != b]
    assert not differ, f"{len(differ)} frames differ after another play, the first at video frame {differ[0]}"
