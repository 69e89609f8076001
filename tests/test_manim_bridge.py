"""The manim bridge: a collisim Trajectory playing inside a manim scene on its own clock. Skipped
without the manim extra (pip install -e '.[test,manim]'), except the checks that collisim works
without it."""
import importlib
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import collisim
from conftest import decode_video

WIDTH, CENTER = 8.0, np.array([1.0, -0.5, 0.0])  # two_bodies' 16 x 9 box at 0.5 manim units per world unit


@pytest.fixture(scope="module")
def manim():
    return pytest.importorskip("manim")


@pytest.fixture(scope="module")
def traj():
    return collisim.simulate(collisim.load_scene("two_bodies").replace(seconds=0.5))


def mapped(traj, points):
    """World points (k, 2) -> manim points (k, 3) for WIDTH and CENTER, computed independently."""
    box = traj.world.box
    scale = WIDTH / (box[2] - box[0])
    xy = CENTER[:2] + scale * (np.asarray(points) - 0.5 * (box[:2] + box[2:]))
    return np.column_stack([xy, np.zeros(len(xy))])


def centres(mobject) -> np.ndarray:
    return np.array([circle.get_center() for circle in mobject.bodies])


def test_renders_in_a_manim_scene_and_holds_the_last_state(manim, traj, tmp_path):
    from collisim.bridges.manim import TrajectoryMobject

    class Collision(manim.Scene):
        def construct(self):
            self.player = TrajectoryMobject(traj, width=WIDTH, center=CENTER)
            self.add(self.player)
            self.wait(1)  # longer than the 0.5 s trajectory: it must stop at the end

    options = {"quality": "low_quality", "frame_rate": 15, "media_dir": str(tmp_path), "disable_caching": True,
               "progress_bar": "none", "verbosity": "WARNING"}
    with manim.tempconfig(options):
        scene = Collision()
        scene.render()
        video = Path(scene.renderer.file_writer.movie_file_path)
    assert video.exists() and video.is_relative_to(tmp_path)
    count, width, height = decode_video(video)[:3]
    assert (count, width, height) == (15, 854, 480)
    player = scene.player
    assert player.time == traj.times[-1]
    np.testing.assert_allclose(centres(player), mapped(traj, traj.positions[-1]), rtol=0, atol=1e-9)
    radii = [circle.width / 2 for circle in player.bodies]
    np.testing.assert_allclose(radii, traj.world.radii * WIDTH / 16.0, rtol=1e-9)
    assert [circle.get_fill_color().to_hex().lower() for circle in player.bodies] == \
        ["#%02x%02x%02x" % tuple(rgb) for rgb in traj.world.colors]


def test_clock_is_frame_rate_independent_and_linear_between_samples(manim, traj):
    from collisim.bridges.manim import TrajectoryMobject

    at_60, at_24 = (TrajectoryMobject(traj, width=WIDTH, center=CENTER) for _ in range(2))
    for _ in range(15):
        at_60.update(1 / 60)  # what manim's updaters get: the frame's dt
    for _ in range(6):
        at_24.update(1 / 24)
    assert at_60.time == pytest.approx(0.25) and at_24.time == pytest.approx(0.25)
    np.testing.assert_allclose(centres(at_60), centres(at_24), rtol=0, atol=1e-9)

    between = 0.3 * traj.times[7] + 0.7 * traj.times[8]
    at_60.seek(between)
    expected = 0.3 * traj.positions[7] + 0.7 * traj.positions[8]
    np.testing.assert_allclose(centres(at_60), mapped(traj, expected), rtol=0, atol=1e-9)

    fast = TrajectoryMobject(traj, width=WIDTH, center=CENTER, playback_rate=2.0)
    for _ in range(30):
        fast.update(1 / 60)  # 0.5 scene seconds at twice the speed: past the end, held there
    assert fast.time == traj.times[-1]
    np.testing.assert_allclose(centres(fast), mapped(traj, traj.positions[-1]), rtol=0, atol=1e-9)


def test_follows_the_group_when_it_moves_and_draws_statics(manim):
    from collisim.bridges.manim import TrajectoryMobject

    world = collisim.World([[2.0, 2.0]], [[1.0, 0.0]], 0.5, box=(0, 0, 8, 4), segments=[[4, 1, 4, 3]])
    traj = collisim.simulate(collisim.Scene(world=world, fps=30, seconds=0.5))
    player = TrajectoryMobject(traj)  # fits the frame
    assert player.outline.width == pytest.approx(0.9 * manim.config.frame_width)
    np.testing.assert_allclose(player.segment_lines[0].get_start(), player.to_manim([[4, 1]])[0], atol=1e-9)
    player.shift([1.0, 2.0, 0.0])
    player.update(0.5)
    np.testing.assert_allclose(player.bodies[0].get_center(), player.to_manim(traj.positions[-1])[0], atol=1e-9)
    with pytest.raises(ValueError, match="playback_rate must be a finite number > 0"):
        TrajectoryMobject(traj, playback_rate=0)
    with pytest.raises(ValueError, match="takes a collisim Trajectory"):
        TrajectoryMobject(world)


def test_polygons_are_drawn_as_their_shapes_turned_with_the_bodies(manim):
    """Each polygon body is a manim Polygon whose corners are the world's placed vertices at
    every time played, also after the group was moved and scaled; circles stay circles."""
    from collisim.bridges.manim import TrajectoryMobject

    traj = collisim.simulate(collisim.load_scene("polygons").replace(seconds=1.0))
    world = traj.world
    polygons = [i for i in range(world.n) if world.vertex_start[i + 1] > world.vertex_start[i]]
    assert 0 < len(polygons) < world.n
    player = TrajectoryMobject(traj, width=WIDTH, center=CENTER)
    for t, moved in ((0.0, False), (0.55, False), (1.0, True)):
        if moved:
            player.shift([0.5, -1.0, 0.0]).scale(0.5)
        player.seek(t)
        positions, angles = player.state_at(t)
        placed = world.placed_vertices(positions, angles)
        for i in range(world.n):
            body = player.bodies[i]
            if i in polygons:
                assert isinstance(body, manim.Polygon)
                expected = player.to_manim(placed[world.vertex_start[i]:world.vertex_start[i + 1]])
                np.testing.assert_allclose(body.get_vertices(), expected, rtol=0, atol=1e-9)
            else:
                assert isinstance(body, manim.Circle)
                np.testing.assert_allclose(body.get_center(), player.to_manim(positions[i:i + 1])[0], atol=1e-9)
                # its radius from its anchors: a turned Circle's width also spans its Bezier handles
                reach = np.linalg.norm(body.get_anchors() - body.get_center(), axis=1)
                np.testing.assert_allclose(reach, player.world_scale * world.radii[i], rtol=1e-9)


def test_a_collision_map_is_drawn_as_its_outlines(manim):
    from collisim.bridges.manim import TrajectoryMobject

    runs = collisim.simulate(collisim.load_scene("collision_map").replace(seconds=0.1))   # one run a panel
    traj = next(run for run in runs if run.world.map is not None)
    chains = traj.world.map.chains
    player = TrajectoryMobject(traj, width=WIDTH, center=CENTER)
    assert len(player.map_outlines) == len(chains) > 0
    for outline, chain in zip(player.map_outlines, chains):
        np.testing.assert_allclose(outline.get_vertices(), player.to_manim(chain), rtol=0, atol=1e-9)


def test_collisim_does_not_import_manim():
    code = "import sys, collisim; assert 'manim' not in sys.modules and 'collisim.bridges' not in sys.modules"
    subprocess.run([sys.executable, "-c", code], check=True, timeout=120)


def test_bridge_without_manim_says_how_to_get_it(monkeypatch):
    monkeypatch.setitem(sys.modules, "manim", None)  # as if manim were not installed
    monkeypatch.delitem(sys.modules, "collisim.bridges.manim", raising=False)
    with pytest.raises(ImportError, match=r"^the manim bridge needs the manim extra: pip install 'collisim\[manim\]'$"):
        importlib.import_module("collisim.bridges.manim")
