"""The slides' hierarchy of bounding volumes: boxes, triangles, a hexagon and two balls drifting
and spinning (no gravity, e = 1, no friction), each drawn with its bounding circle, box and
oriented box; pairs whose volumes overlap while their shapes do not are marked as false
positives, and the funnel of counts per level (the engine's) stands beside."""
import numpy as np

import collisim
from collisim.render import volumes
from collisim.render.explain import Caption, Explainer, Figure
from collisim.shapes import box, regular

BOX = (0.0, 0.0, 16.0, 9.0)
SECONDS = 10.0
# long, flat shapes fill little of their circles and, turned, little of their boxes
SHAPES = [box(2.4, 0.4), box(1.2, 1.2), regular(3, 0.9), regular(6, 0.75), None, box(1.8, 0.6), regular(3, 0.7),
          None, box(2.0, 0.3)]
RADII = [1.0, 1.0, 1.0, 1.0, 0.6, 1.0, 1.0, 0.45, 1.0]   # the balls' (a polygon's comes from its vertices)
# the bodies in purples, pinks and slate, apart from the volumes' blue, green and orange, the
# false positives' red and the touching pairs' yellow
COLORS = [(190, 140, 255), (150, 160, 190), (255, 122, 190), (120, 110, 200), (150, 160, 190), (255, 122, 190),
          (190, 140, 255), (120, 110, 200), (150, 160, 190)]


def world() -> collisim.World:
    rng = np.random.default_rng(10)
    cells = [(x, y) for y in (1.6, 4.5, 7.4) for x in (2.7, 8.0, 13.3)]   # apart: 2.9 > two of the largest reach
    positions = np.array(cells) + rng.uniform(-0.3, 0.3, (len(cells), 2))
    velocities = rng.normal(0.0, 1.6, (len(cells), 2))
    return collisim.World(positions, velocities, radii=RADII, polygons=SHAPES, angles=rng.uniform(0, np.pi, len(cells)),
                          angular_velocities=rng.uniform(-2.0, 2.0, len(cells)), box=BOX, restitution=1.0,
                          friction=0.0, colors=COLORS)


FADE = 0.2


def explainer(shared: collisim.World) -> Explainer:
    """Captions in turn on the top strip's second line (each gone before the next fades in),
    the legend below, the volumes over the bodies and the funnel beside them."""
    turns = np.linspace(0.0, SECONDS, 5)
    lessons = ["bounding circles (blue): one distance, the cheapest test and the coarsest: a long shape fills "
               "little of its circle",
               "boxes (green): four comparisons; tight on a shape lined up with the axes, loose once it turns",
               "oriented boxes (orange) turn with the shape: tighter, and dearer: projections on four axes",
               "the exact test is the dearest, on the fewest pairs: false positives shrink down the funnel"]
    items = [Caption(r"bounding circle $\rightarrow$ box $\rightarrow$ oriented box $\rightarrow$ shape: each test "
                     r"only sees the pairs the coarser one let through", 0.0, None, "top")]
    items += [Caption(text, start + (FADE if k else 0.0), end - FADE if k < 3 else None, "top", 1)
              for k, (text, start, end) in enumerate(zip(lessons, turns, turns[1:]))]
    items += [Caption("red: volumes overlap, shapes do not (a false positive), tagged with the last volume that let "
                      "it through; yellow: the shapes touch", 0.0, None, "bottom"),
              Figure(volumes.volumes_figure(shared), 0.0, None, "box"),
              Figure(volumes.funnel_figure, 0.0, None, "side")]
    return Explainer(items, fade=FADE, lines=(2, 1), side=0.3)


def scene() -> collisim.Scene:
    shared = world()
    settings = collisim.RenderSettings(explainer=explainer(shared), counters=volumes.counters(), flash=False)
    return collisim.Scene(world=shared, fps=60, seconds=SECONDS, method="discrete", name="bounding_volumes",
                          render=settings)
