"""Every shipped scene: it loads, no two bodies start overlapping (nor a body and a segment or a
map), and its opening renders to a video whose frames decode. A scene added to scenes/ is
covered without touching this file."""
from fractions import Fraction

import pytest

import collisim
from collisim.model.scenefile import available_scenes
from collisim import contacts
from collisim.narrowphase.statics import touching_segments
from conftest import decode_video

SCENES = sorted(available_scenes())


def worlds(scene):
    """Every world a scene holds, through its panels and chapters."""
    if scene.world is not None:
        return [scene.world]
    parts = [panel.scene for panel in scene.panels] + list(scene.chapters)
    return [world for part in parts for world in worlds(part)]


def test_the_shipped_scenes_are_all_found():
    assert {"particles_250", "single_bounce", "two_bodies", "frame_rate", "broadphase_six", "tunneling",
            "raycast", "collision_map"} <= set(SCENES)


@pytest.mark.parametrize("name", SCENES)
def test_no_scene_starts_with_bodies_overlapping(name):
    for world in worlds(collisim.load_scene(name)):
        if world.n >= 2:
            found = contacts(world)
            assert (found["depths"] <= 1e-12 * world.radii.max()).all(), found["pairs"][found["depths"].argmax()]
        if len(world.level_segments):
            _, depths = touching_segments(world.positions, world.radii, world.level_segments, world.box)
            assert (depths <= 1e-12 * world.radii.max()).all()
        if world.map is not None:
            assert (world.map.distance(world.positions) > world.radii - world.map.cell).all()


@pytest.mark.parametrize("name", SCENES)
def test_every_scene_opens_on_video(name, tmp_path):
    scene = collisim.load_scene(name).with_options(seconds=0.2)
    frames = collisim.pipeline.plan(scene, size=(320, 180), fps=15).frames   # 3, plus any slow motion
    out = collisim.render(scene, tmp_path / f"{name}.mp4", size=(320, 180), fps=15)
    count, width, height, rate, codec, _ = decode_video(out)
    assert (count, width, height, rate, codec) == (frames, 320, 180, Fraction(15), "h264")
    assert frames >= 3
