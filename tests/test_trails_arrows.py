"""Trails and velocity arrows survive H.264 at -ql (decoded, they stand clearly apart from the
background) and never leave the box (an arrow pointing at a wall is cut at the wall)."""
import numpy as np
import pytest

import collisim
from collisim import palette
from collisim.render.view import View

BOX = (0.0, 0.0, 10.0, 6.0)
SECONDS = 1.0


@pytest.fixture(scope="module")
def last_frame(tmp_path_factory):
    """The last decoded frame of a -ql render: a ball crossing the middle with a trail and an
    arrow, and a slow one heading for the right wall with an arrow longer than its way there."""
    import av
    world = collisim.World(positions=[[2.0, 3.0], [8.0, 1.5]], velocities=[[4.0, 0.0], [1.0, 0.0]],
                           radii=[0.4, 0.3], box=BOX, colors=[(94, 172, 255), (255, 122, 190)])
    settings = collisim.RenderSettings(trails=20, arrows=True, arrow_seconds=1.5, hud=False, flash=False)
    scene = collisim.Scene(world=world, fps=60, seconds=SECONDS, render=settings)
    out = collisim.render(scene, tmp_path_factory.mktemp("trails") / "trails.mp4", quality="l")
    with av.open(str(out)) as container:
        frames = [frame.to_ndarray(format="rgb24") for frame in container.decode(video=0)]
    job = collisim.pipeline.plan(scene, quality="l")
    time = np.floor((job.frames - 1) / job.fps * 60 + 1e-9) / 60      # the sample the last frame shows
    return frames[-1].astype(int), View(BOX, (0, 0, *job.size)), time


def colour_at(frame, view, point):
    x, y = np.rint(view.to_pixels(point)).astype(int)
    return frame[y, x]


def distance(a, b):
    return float(np.abs(np.asarray(a, int) - np.asarray(b, int)).max())


def test_a_trail_stays_clearly_visible_after_encoding(last_frame):
    frame, view, time = last_frame
    ball = 2.0 + 4.0 * time
    for back in (0.3, 0.7):                  # behind the ball's rim, on the 1.27 of path the trail keeps
        seen = colour_at(frame, view, [ball - 0.4 - back, 3.0])
        assert distance(seen, palette.BACKGROUND) > 60, (back, seen)
        assert seen[2] > seen[0] + 40         # still the ball's blue, not a grey smear


def test_an_arrow_shows_outside_its_ball_and_stays_in_the_box(last_frame):
    frame, view, time = last_frame
    ball = 2.0 + 4.0 * time
    tip = ball + 0.4 + 4.0 * 1.5             # the arrow starts at the rim: its tip is past the ball
    seen = colour_at(frame, view, [0.5 * (ball + 0.4 + min(tip, 10.0)), 3.0])
    assert distance(seen, palette.BACKGROUND) > 100, seen
    slow = 8.0 + time                        # 0.3 from the wall... and an arrow 1.5 long: cut at the wall
    assert distance(colour_at(frame, view, [0.5 * (slow + 0.3 + 10.0), 1.5]), palette.BACKGROUND) > 100


def test_nothing_is_drawn_outside_the_box(last_frame):
    frame, view, _ = last_frame
    (x0, y1), (x1, y0) = np.rint(view.to_pixels([[BOX[0], BOX[1]], [BOX[2], BOX[3]]])).astype(int)
    outside = np.ones(frame.shape[:2], bool)
    band = 4                                 # the box's own outline, and the encoder's ringing next to it
    outside[y0 - band:y1 + band + 1, x0 - band:x1 + band + 1] = False
    assert outside.sum() > 0.1 * outside.size
    assert np.abs(frame[outside] - np.array(palette.BACKGROUND)).max() <= 12
