"""Frames and interpolation: a circle carried from A to B at 15 and at 60 frames per second, then the 15 fps frames as ghosts with the linear interpolation filling them in."""
import numpy as np

import collisim
from collisim import palette
from collisim.render import raster
from collisim.render.explain import Caption, Explainer

RADIUS = 0.5
A, B = np.array([RADIUS, 1.2]), np.array([12.0 - RADIUS, 1.2])
TRAVEL_SECONDS = 1.0  # from A to B; the walls at A and B send it back
BOX = (0.0, 0.0, 12.0, 2.4)


def world() -> collisim.World:
    # Constant velocity makes each step exactly the linear interpolation A + (B - A)·t/T.
    return collisim.World(positions=[A], velocities=[(B - A) / TRAVEL_SECONDS], radii=RADIUS, box=BOX)


def ab_labels(canvas, view, state):
    tick = view.length(0.12)
    for label, point in (("A", A), ("B", B)):
        x, y = view.to_pixels(point)
        raster.draw_text(canvas, label, (x, y - view.length(RADIUS) - tick), scale=0.7,
                         color_rgb=palette.HIGHLIGHT, thickness=2, anchor="center")


def side_by_side(seconds) -> collisim.Scene:
    panels = []
    for fps, text in ((15, r"15 frames a second: 15 positions, the circle jumps $\frac{1}{15}$ of the way"),
                      (60, r"60 frames a second: 60 positions, the motion looks smooth")):
        explainer = Explainer([Caption(text, 0.0, None, "top")], lines=1)
        settings = collisim.RenderSettings(flash=False, overlay=ab_labels, explainer=explainer)
        panels.append(collisim.Panel(collisim.Scene(world=world(), fps=fps, seconds=seconds, render=settings),
                                     f"{fps} frames per second"))
    return collisim.Scene(panels=panels, fps=60, seconds=seconds, render=collisim.RenderSettings(layout=(2, 1)))


class Ghosts:
    """The samples seen so far as faint circles (read off the trajectory as it plays), and,
    between the last two, the interpolated circle p(t) = (1 - t) p0 + t p1 sweeping across
    while each sample is held on screen."""

    def __init__(self, fps):
        self.fps = fps

    def __call__(self, canvas, view, state):
        samples = state.memory.setdefault("ghosts", {})   # sample -> position, for this play only
        samples[state.sample] = state.positions[0].copy()
        recent = [samples[k] for k in sorted(samples)][-self.fps:]
        radius = view.length(RADIUS)
        raster.draw_rings(canvas, view.to_pixels(np.array(recent)), np.full(len(recent), radius),
                          palette.DIM_TEXT, 1)
        ab_labels(canvas, view, state)
        if state.sample >= 1 and state.sample - 1 in samples:
            p0, p1 = samples[state.sample - 1], samples[state.sample]
            t = (state.clock * self.fps) % 1.0          # how far through the hold of this sample
            between = (1.0 - t) * p0 + t * p1
            raster.draw_rings(canvas, view.to_pixels(between[None]), [radius], palette.HIGHLIGHT, 2)


def interpolation(seconds) -> collisim.Scene:
    fps = 15
    explainer = Explainer([
        Caption(r"the 15 frames of each second, kept as ghosts: the spacing is the distance moved in one frame",
                0.0, None, "top"),
        Caption(r"between two frames, linear interpolation: $p(t) = (1 - t)\,p_0 + t\,p_1$, $t$ from 0 to 1",
                1.0, None, "top", 1),
    ], lines=2)
    settings = collisim.RenderSettings(flash=False, overlay=Ghosts(fps), explainer=explainer)
    scene = collisim.Scene(world=world(), fps=fps, seconds=seconds, render=settings)
    return collisim.Scene(panels=[collisim.Panel(scene, "ghosts and interpolation at 15 fps")], fps=60,
                          seconds=seconds)


def scene() -> collisim.Scene:
    seconds = 2 * TRAVEL_SECONDS * 2
    return collisim.Scene(chapters=[side_by_side(seconds), interpolation(seconds)], fps=60, seconds=2 * seconds,
                          render=collisim.RenderSettings(min_fps=60))   # the lesson needs 60 fps video, even at -ql
