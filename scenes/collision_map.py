"""A collision map: particles poured through a pinball table painted as a PNG, under discrete and ccd."""
from pathlib import Path

import numpy as np

import collisim

LEVEL = Path(__file__).with_name("pinball.png")   # drawn by _pinball_level.py; black is solid
CELL = 0.05                                      # world units per pixel: 640 x 360 pixels -> 32 x 18
BOX = (0.0, 0.0, 32.0, 18.0)
RADIUS = 0.16


def level() -> collisim.CollisionMap:
    """The table: a distance field for the discrete method, exact outlines for ccd."""
    return collisim.CollisionMap.from_image(LEVEL, cell=CELL, origin=BOX[:2])


def poured(table: collisim.CollisionMap, seed: int = 5) -> collisim.World:
    """Four rows of particles above the funnel, drifting sideways, about to fall. Elastic, so
    they keep bouncing through the pegs rather than coming to rest in the bins."""
    rng = np.random.default_rng(seed)
    xs, ys = np.meshgrid(np.arange(1.2, 31.0, 0.75), np.arange(15.7, 17.3, 0.5))
    positions = np.column_stack([xs.ravel(), ys.ravel()])
    positions = positions[table.distance(positions) > 1.5 * RADIUS]
    velocities = np.column_stack([rng.normal(0.0, 1.5, len(positions)), rng.normal(0.0, 0.5, len(positions))])
    return collisim.World(positions=positions, velocities=velocities, radii=RADIUS, box=BOX, gravity=(0.0, -9.8),
                          restitution=1.0, map=table)


def scene() -> collisim.Scene:
    world = poured(level())
    panels = [collisim.Panel(collisim.Scene(world=world, fps=60, seconds=12.0, method=method, substeps=substeps,
                                            render=collisim.RenderSettings(flash=True)), title)
              for method, substeps, title in (("discrete", 2, "discrete: the distance field, 2 substeps"),
                                              ("ccd", 1, "ccd: the exact outlines"))]
    return collisim.Scene(panels=panels, fps=60, seconds=12.0)
