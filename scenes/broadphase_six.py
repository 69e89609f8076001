"""Six particles, once per broad phase, with each structure drawn over them and its candidate pairs highlighted."""
import numpy as np

import collisim
from collisim import palette
from collisim.broadphase import describe, make
from collisim.model.kinds import PAIR
from collisim.render import raster
from collisim.render.explain import Caption, Explainer

TITLES = {"brute": "brute force", "sweep_prune": "sweep and prune", "grid": "uniform grid",
          "kdtree": "kd-tree", "bvh": "bounding volume hierarchy"}
BOX = (0.0, 0.0, 10.0, 6.0)
# the video's six: pink, orange, blue, red, yellow, green
COLORS = [(255, 122, 190), (255, 160, 60), (94, 172, 255), (240, 80, 80), (255, 226, 110), (120, 220, 160)]
STRUCTURE = (150, 156, 175)
# split down to single particles, as the video does, so every level of the trees shows
OPTIONS = {"kdtree": {"leaf_size": 1}, "bvh": {"leaf_size": 1}}


def six_particles():
    # as in the video, two pairs start with overlapping boxes (but apart): pink-orange and red-yellow
    positions = np.array([[1.8, 4.2], [3.2, 3.1], [5.0, 1.8], [6.6, 4.3], [8.0, 3.25], [8.4, 1.4]])
    velocities = np.array([[0.3, -0.2], [-0.2, 0.25], [0.3, 0.3], [-0.25, -0.15], [0.2, 0.25], [-0.3, 0.2]])
    radii = np.array([0.8, 0.75, 0.85, 0.75, 0.85, 0.8])
    return positions, velocities, radii


def draw_pairs(canvas, view, positions, pairs, color, thickness):
    if len(pairs):
        raster.draw_lines(canvas, view, positions[pairs[:, 0]], positions[pairs[:, 1]], color, thickness)


def draw_sweep(canvas, view, info, lo, hi):
    """The projected intervals on the sweep axis, stacked in sorted order, and the final active list."""
    axis, order = info["axis"], info["order"]
    xmin, ymin, xmax, ymax = BOX
    for rank, i in enumerate(order):
        a, b = info["intervals"][i]
        offset = 0.15 + 0.12 * rank
        if axis == 0:
            start, end = [a, ymin + offset], [b, ymin + offset]
        else:
            start, end = [xmin + offset, a], [xmin + offset, b]
        raster.draw_lines(canvas, view, [start], [end], COLORS[i], 3)
    active = ", ".join(str(i) for i in info["active_steps"][-1]) if info["active_steps"] else ""
    x, y = view.to_pixels([xmax, ymin])
    raster.draw_text(canvas, f"sweep {'xy'[axis]}, active list: [{active}]", (x - 4, y - 8), scale=0.38,
                     color_rgb=palette.DIM_TEXT, anchor="right")


def draw_grid(canvas, view, info):
    nx, ny = info["shape"]
    size, (ox, oy) = info["cell_size"], info["origin"]
    xmin, ymin, xmax, ymax = BOX  # the grid covers the boxes; draw the part inside the world
    xs = np.clip(ox + size * np.arange(nx + 1), xmin, xmax)
    ys = np.clip(oy + size * np.arange(ny + 1), ymin, ymax)
    raster.draw_lines(canvas, view, np.column_stack([xs, np.full_like(xs, ys[0])]),
                      np.column_stack([xs, np.full_like(xs, ys[-1])]), STRUCTURE, 1)
    raster.draw_lines(canvas, view, np.column_stack([np.full_like(ys, xs[0]), ys]),
                      np.column_stack([np.full_like(ys, xs[-1]), ys]), STRUCTURE, 1)
    for cx, cy in zip(*np.nonzero(info["counts"])):
        x, y = view.to_pixels([ox + (cx + 0.1) * size, oy + (cy + 0.1) * size])
        raster.draw_text(canvas, str(info["counts"][cx, cy]), (x, y), scale=0.35, color_rgb=palette.HIGHLIGHT)


def draw_kdtree(canvas, view, info):
    for axis, value, node_lo, node_hi, depth in info["splits"]:
        start, end = np.array(node_lo, float), np.array(node_hi, float)
        start[axis] = end[axis] = value
        raster.draw_lines(canvas, view, [start], [end], STRUCTURE, max(1, 3 - depth))


def draw_bvh(canvas, view, info):
    for node_lo, node_hi, depth, is_leaf in info["nodes"]:
        color = palette.pick(depth + 3) if not is_leaf else STRUCTURE
        raster.draw_rects(canvas, view, [node_lo], [node_hi], color, 1)


DRAW = {"sweep_prune": lambda c, v, info, lo, hi: draw_sweep(c, v, info, lo, hi),
        "grid": lambda c, v, info, lo, hi: draw_grid(c, v, info),
        "kdtree": lambda c, v, info, lo, hi: draw_kdtree(c, v, info),
        "bvh": lambda c, v, info, lo, hi: draw_bvh(c, v, info)}


def plural(count, word):
    return f"{count} {word}{'' if count == 1 else 's'}"


def broad_caption(method, state, total):
    """The panel's caption, from the engine's own count of this frame's candidates."""
    if method == "brute":
        return f"brute force: tests all {total} pairs; {plural(state.candidates, 'pair')} of boxes overlap"
    return f"{TITLES[method]}: {plural(state.candidates, 'candidate pair')} of {total}"


def explainer(method, radii):
    def overlay(canvas, view, state):
        positions = state.positions
        lo, hi = positions - radii[:, None], positions + radii[:, None]
        phase = make(method, **OPTIONS.get(method, {}))
        info = phase.describe(lo, hi)
        if method in DRAW:
            DRAW[method](canvas, view, info, lo, hi)
        all_pairs = np.column_stack(np.triu_indices(len(positions), 1))
        if method == "brute":
            draw_pairs(canvas, view, positions, all_pairs, STRUCTURE, 1)
        draw_pairs(canvas, view, positions, info["pairs"], palette.HIGHLIGHT, 2)
    return overlay


def grid_note(radii):
    """The grid's trade-off, memory for fewer checks, for the caption strip."""
    def text(state):
        lo, hi = state.positions - radii[:, None], state.positions + radii[:, None]
        phase = make("grid")
        nx, ny = phase.describe(lo, hi)["shape"]
        return f"{nx} x {ny} cells; the cell lists take {phase.stats['memory_bytes']} bytes"
    return text


def captions(method, radii):
    """The panel's captions, in a strip above the box: the engine's count, and the grid's memory."""
    items = [Caption(lambda state: broad_caption(method, state, 15), 0.0, None, "top")]
    if method == "grid":
        items.append(Caption(grid_note(radii), 0.0, None, "top", 1))
    return Explainer(items, fade=0.0, lines=2)


def touching_now(state):
    """The pairs the engine found touching in the step that ended at this sample (its PAIR events)."""
    now = (state.events.kind == PAIR) & (np.abs(state.events.time - state.time) < 1e-9)
    return np.column_stack([state.events.i[now], state.events.j[now]])


def narrow_caption(state):
    """The engine's counts for this sample: its candidates and the pairs that touched."""
    return (f"narrow phase: {plural(state.pair_collisions, 'pair')} of "
            f"{plural(state.candidates, 'candidate')} touched")


def narrow_phase(radii):
    """What every broad phase hands on: the candidates, and the pairs that really touch."""
    def overlay(canvas, view, state):
        positions = state.positions
        pairs = describe("sweep_prune", positions - radii[:, None], positions + radii[:, None])["pairs"]
        draw_pairs(canvas, view, positions, pairs, palette.HIGHLIGHT, 1)
        draw_pairs(canvas, view, positions, touching_now(state), palette.FLASH, 3)
    return overlay


def panel(method):
    positions, velocities, radii = six_particles()
    world = collisim.World(positions=positions, velocities=velocities, radii=radii, box=BOX, colors=COLORS)
    settings = collisim.RenderSettings(hud=False, flash=True, overlay=explainer(method, radii),
                                       explainer=captions(method, radii))
    scene = collisim.Scene(world=world, fps=60, seconds=12.0, broadphase=method, render=settings)
    return collisim.Panel(scene, TITLES[method])


def narrow_panel():
    positions, velocities, radii = six_particles()
    world = collisim.World(positions=positions, velocities=velocities, radii=radii, box=BOX, colors=COLORS)
    settings = collisim.RenderSettings(hud=False, flash=True, overlay=narrow_phase(radii),
                                       explainer=Explainer([Caption(narrow_caption, 0.0, None, "top")], fade=0.0,
                                                           lines=2))
    return collisim.Panel(collisim.Scene(world=world, fps=60, seconds=12.0, render=settings),
                          "then the narrow phase: exact tests")


def scene() -> collisim.Scene:
    panels = [panel(method) for method in ("brute", "sweep_prune", "grid", "kdtree", "bvh")] + [narrow_panel()]
    return collisim.Scene(panels=panels, fps=60, seconds=12.0, render=collisim.RenderSettings(layout=(2, 3)))
