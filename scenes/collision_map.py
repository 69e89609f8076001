"""A collision map: particles poured through a pinball table painted as a PNG, under discrete and ccd."""
from pathlib import Path

import numpy as np

import collisim
from collisim.core.kinds import MAP
from collisim.render.explain import Caption, Explainer

LEVEL = Path(__file__).with_name("pinball.png")   # drawn by _pinball_level.py; black is solid
CELL = 0.05                                      # world units per pixel: 640 x 360 pixels -> 32 x 18
BOX = (0.0, 0.0, 32.0, 18.0)
RADIUS = 0.16


def level() -> collisim.CollisionMap:
    """The table: a distance field for the discrete method, its outlines (to a pixel) for ccd."""
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


def map_contacts(state) -> str:
    """The engine's contacts with the map so far (its MAP events)."""
    return f"contacts with the map so far: {int(np.sum(state.events.kind == MAP))}"


def distance_field_notes(table: collisim.CollisionMap) -> Explainer:
    """The slides' words for the discrete panel, with the map's own numbers."""
    ny, nx = table.shape
    return Explainer([
        Caption(f"a collision map, precomputed: {nx} x {ny} cells", 0.0, None, "top"),
        Caption(f"accuracy = resolution: cell {table.cell:g} = radius / {RADIUS / table.cell:.1f}",
                0.0, None, "top", 1),
        Caption(map_contacts, 0.0, None, "bottom"),
    ], lines=(2, 1))


def outline_notes(table: collisim.CollisionMap) -> Explainer:
    return Explainer([
        Caption(f"ccd: its outlines, {len(table.segments)} segments", 0.0, None, "top"),
        Caption("exact times, outlines as fine as its pixels", 0.0, None, "top", 1),
        Caption(map_contacts, 0.0, None, "bottom"),
    ], lines=(2, 1))


def scene() -> collisim.Scene:
    world = poured(level())
    notes = {"discrete": distance_field_notes(world.map), "ccd": outline_notes(world.map)}
    panels = [collisim.Panel(collisim.Scene(world=world, fps=60, seconds=12.0, method=method, substeps=substeps,
                                            render=collisim.RenderSettings(flash=True, explainer=notes[method])), title)
              for method, substeps, title in (("discrete", 2, "discrete: the distance field, 2 substeps"),
                                              ("ccd", 1, "ccd: the exact outlines"))]
    return collisim.Scene(panels=panels, fps=60, seconds=12.0)
