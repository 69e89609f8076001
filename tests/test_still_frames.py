"""-s and --png N simulate to their frame and draw only it: the still has the pixels of the
video's frame, for a plain scene and for explained ones whose overlays keep memory across frames
(frame_rate's ghosts, two_bodies' velocities at the impact), across chapters and slow motion."""
import cv2
import numpy as np
import pytest

import collisim
from collisim.render import player

SIZE = (320, 180)


def shipped(name):
    """The scene; particles_250 cut to 2 s, with trails (what a plain scene's still must rebuild)."""
    scene = collisim.load_scene(name)
    if name == "particles_250":
        scene = scene.replace(seconds=2.0, render=collisim.RenderSettings(trails=6, flash=True))
    return scene


def sequence(scene, folder, fps):
    collisim.render(scene, folder, SIZE, fps=fps, format="png")
    return sorted(folder.iterdir())


@pytest.mark.parametrize("name, fps, frames", [
    ("particles_250", 30, (0, 17, -1)),      # no overlay: trails, flashes and the HUD's counts
    ("single_bounce", 30, (0, 17, -1)),
    ("frame_rate", 15, (9, 60, 75, -1)),      # chapter one (two panels), chapter two (ghosts in memory)
    ("two_bodies", 15, (20, 45, -1)),         # a note that keeps the velocities read at the impact
])
def test_a_still_is_the_video_s_frame(tmp_path, name, fps, frames):
    scene = shipped(name)
    files = sequence(scene, tmp_path / "seq", fps)
    for frame in frames:
        frame = frame % len(files)
        still = collisim.render(scene, tmp_path / f"still{frame}.png", SIZE, fps=fps, png_frame=frame)
        np.testing.assert_array_equal(cv2.imread(str(still)), cv2.imread(str(files[frame])), err_msg=f"frame {frame}")


def test_a_still_draws_one_frame_when_nothing_keeps_memory(tmp_path, monkeypatch):
    """particles_250's last frame: its panel simulated to it and drawn once."""
    drawn = []
    draw = player.PanelPlayer.draw
    monkeypatch.setattr(player.PanelPlayer, "draw", lambda self, canvas: drawn.append(1) or draw(self, canvas))
    scene = shipped("particles_250")
    collisim.render(scene, tmp_path / "last.png", SIZE, last_frame=True)
    assert len(drawn) == 1


def ghost_overlay(canvas, view, state):
    """Rings where the bodies were at the panel's first sample, kept in state.memory."""
    from collisim import palette
    from collisim.render import raster
    first = state.memory.setdefault("first", state.positions.copy())
    raster.draw_rings(canvas, view.to_pixels(first), [4.0] * len(first), palette.TEXT, 1)


def test_a_still_of_panels_in_rows_that_keep_memory_is_drawn_at_the_video_s_scale():
    """Four titled panels in two rows whose overlay keeps memory: the still plays them again from
    the chapter's start, and played again they are drawn at the frame's scale (their HUD and
    titles), as in the video, not at their own smaller panel's."""
    from collisim.render.timeline import Timeline
    panels = []
    for k in range(4):
        world = collisim.World([[2.0 + k, 5.0], [7.0, 5.0]], [[2.0, 0.5], [-1.0, 0.0]], radii=0.5)
        settings = collisim.RenderSettings(overlay=ghost_overlay)
        panels.append(collisim.Panel(collisim.Scene(world=world, fps=30, seconds=1.0, render=settings), f"panel {k}"))
    scene = collisim.Scene(panels=panels, fps=30, seconds=1.0)
    job = collisim.pipeline.plan(scene, size=(1280, 720), fps=15)   # panels of 360 rows, text as at 720
    timelines = [Timeline(job.chapters, job.size, job.fps) for _ in range(2)]
    frame = 10
    video, still = (np.empty((720, 1280, 3), np.uint8) for _ in range(2))
    for earlier in range(frame + 1):
        timelines[0].draw(video, earlier)
    timelines[1].draw_alone(still, frame)
    for timeline in timelines:
        timeline.close()
    np.testing.assert_array_equal(still, video)
