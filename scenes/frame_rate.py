"""A circle carried from A to B by linear interpolation at 15 and at 60 frames per second, side by side."""
import numpy as np

import collisim
from collisim import palette
from collisim.render import raster

RADIUS = 0.5
A, B = np.array([RADIUS, 1.2]), np.array([12.0 - RADIUS, 1.2])
TRAVEL_SECONDS = 1.0  # from A to B; the walls at A and B send it back


def panel(fps: int, seconds: float) -> collisim.Panel:
    # Constant velocity makes each step exactly the linear interpolation A + (B - A)·t/T.
    world = collisim.World(positions=[A], velocities=[(B - A) / TRAVEL_SECONDS], radii=RADIUS,
                           box=(0.0, 0.0, 12.0, 2.4))
    settings = collisim.RenderSettings(hud=True, flash=False, overlay=frame_marks(fps, world))
    return collisim.Panel(collisim.Scene(world=world, fps=fps, seconds=seconds, render=settings),
                          title=f"{fps} frames per second")


def frame_marks(fps: int, world):
    """Ticks at the centre of every frame's circle on the way from A to B: the spacing is the step."""
    steps = np.linspace(0.0, 1.0, int(round(fps * TRAVEL_SECONDS)) + 1)
    marks = A + np.outer(steps, B - A)

    def overlay(canvas, view, state):
        pixels = view.to_pixels(marks)
        tick = view.length(0.12)
        for (x, y) in pixels:
            raster.draw_text(canvas, "|", (x, y + view.length(RADIUS) + 2 * tick), scale=0.4,
                             color_rgb=palette.DIM_TEXT, anchor="center")
        for label, point in (("A", A), ("B", B)):
            x, y = view.to_pixels(point)
            raster.draw_text(canvas, label, (x, y - view.length(RADIUS) - tick), scale=0.7,
                             color_rgb=palette.HIGHLIGHT, thickness=2, anchor="center")
    return overlay


def scene() -> collisim.Scene:
    seconds = 2 * TRAVEL_SECONDS * 2
    return collisim.Scene(
        panels=[panel(15, seconds), panel(60, seconds)], fps=60, seconds=seconds,
        render=collisim.RenderSettings(layout=(2, 1)),
    )
