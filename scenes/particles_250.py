"""The video's opening shot: 250 particles of three sizes and colours in a closed box."""
import collisim
from collisim.gas import lattice_gas


def scene() -> collisim.Scene:
    box = (0.0, 0.0, 32.0, 18.0)
    positions, velocities, radii = lattice_gas(250, box=box, speed=3.0, seed=7)
    world = collisim.World(positions=positions, velocities=velocities, radii=radii, box=box)
    return collisim.Scene(world=world, fps=60, seconds=10.0, method="discrete",
                          render=collisim.RenderSettings(flash=True))
