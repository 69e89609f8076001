"""Boxes, triangles and hexagons dropped among balls: they fall, tumble and settle into a pile on
the floor, under gravity, with some bounce and friction (the discrete method's contact solver)."""
import numpy as np

import collisim
from collisim.render.explain import Caption, Explainer
from collisim.shapes import box, regular


def funnel(n: int):
    """The slides' hierarchy on this frame, as the engine counted it (Trajectory.hierarchy)."""
    def text(state):
        if state.hierarchy is None or state.hierarchy[0] < 0:
            return ""
        circles, boxes, oriented, touching = (int(c) for c in state.hierarchy)
        return (f"this frame, of {n * (n - 1) // 2} pairs: {circles} bounding circles overlap, {boxes} boxes, "
                f"{oriented} oriented boxes, {touching} shapes touch")
    return text


def shape_tests(n: int):
    def text(state):
        if state.hierarchy is None or state.hierarchy[0] < 0:
            return ""
        return f"only {int(state.hierarchy[2])} of the {n * (n - 1) // 2} pairs get as far as the exact shape test"
    return text


def explainer(n: int) -> Explainer:
    return Explainer([
        Caption("polygons: the most accurate test, and the most expensive", 0.0, None, "top"),
        Caption("so the cheap volumes go first: bounding circle, then box, then oriented box, then the shape",
                0.0, None, "top", 1),
        Caption(funnel(n), 0.0, None, "bottom"),
        Caption(shape_tests(n), 0.0, None, "bottom", 1),
    ])


def scene() -> collisim.Scene:
    rng = np.random.default_rng(3)
    shapes = [box(1.0, 0.6), regular(3, 0.6), regular(6, 0.5), None]     # None: a ball of radius 0.4
    columns, rows = 10, 6
    positions, polygons, angles = [], [], []
    for k in range(columns * rows):
        positions.append((1.6 + 1.6 * (k % columns) + rng.uniform(-0.2, 0.2), 3.0 + 1.5 * (k // columns)))
        polygons.append(shapes[k % len(shapes)])
        angles.append(rng.uniform(0, np.pi))
    velocities = rng.normal(0.0, 1.0, (len(positions), 2))
    world = collisim.World(positions, velocities, radii=0.4, polygons=polygons, angles=angles,
                           angular_velocities=rng.normal(0.0, 2.0, len(positions)), box=(0.0, 0.0, 17.6, 12.0),
                           gravity=(0.0, -9.81), restitution=0.3, friction=0.4)
    return collisim.Scene(world=world, fps=60, seconds=8.0, method="discrete", name="polygons",
                          render=collisim.RenderSettings(flash=False, explainer=explainer(world.n)))
