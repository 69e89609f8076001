"""One particle under constant acceleration bouncing along the edges of a box (the video's first simulation)."""
import collisim


def scene() -> collisim.Scene:
    world = collisim.World(
        positions=[[1.5, 6.5]],
        velocities=[[3.2, 1.0]],
        radii=0.45,
        box=(0.0, 0.0, 16.0, 9.0),
        gravity=(0.0, -9.8),
    )
    return collisim.Scene(
        world=world, fps=60, seconds=8.0, method="discrete",
        render=collisim.RenderSettings(trails=90, arrows=True),
    )
