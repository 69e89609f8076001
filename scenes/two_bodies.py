"""Two particles of different masses and sizes colliding obliquely with each other and with the walls."""
import collisim


def scene() -> collisim.Scene:
    world = collisim.World(
        positions=[[3.0, 3.2], [12.0, 5.6]],
        velocities=[[4.0, 1.1], [-2.6, -0.4]],
        radii=[0.55, 1.1],            # masses follow the area: the large one is 4x heavier
        box=(0.0, 0.0, 16.0, 9.0),
    )
    return collisim.Scene(
        world=world, fps=60, seconds=10.0, method="discrete",
        render=collisim.RenderSettings(trails=45, arrows=True),
    )
