"""The video's six particles through each broad phase, one chapter per structure built step by step on a frozen frame (brute force, sweep and prune, uniform grid, kd-tree, BVH), then the narrow phase; every count on screen is the engine's."""
import numpy as np

import collisim
from collisim import palette
from collisim.broadphase import describe
from collisim.broadphase.step import GridState, box_grid
from collisim.engine.discrete import bounding_boxes
from collisim.core.kinds import PAIR
from collisim.render import structures as draw
from collisim.render.explain import Caption, Explainer, Figure, image_figure
from collisim.render.pace import Freeze, Pace, Slow, Steps

BOX = (0.0, 0.0, 10.0, 6.0)
# the video's six: pink, orange, blue, red, yellow, green
COLORS = [(255, 122, 190), (255, 160, 60), (94, 172, 255), (240, 80, 80), (255, 226, 110), (120, 220, 160)]
NAMES = ("pink", "orange", "blue", "red", "yellow", "green")
KEY = 1.0 / 60.0     # the frame each structure is built on: the engine's first step (frame 0 has none yet)
AFTER = 3.0          # seconds of simulation played after each build, the structure following the bodies
HOLD = 1.5           # seconds the finished build stays frozen
# split down to single particles, as the video does, so the termination rule shows; the engine's
# own trees stop at two (broadphase/step.py), and every count is the same: exactly the overlapping boxes
TREE_OPTIONS = {"leaf_size": 1}


def six_particles():
    # as in the video, two pairs start with overlapping boxes (but apart): pink-orange and red-yellow
    positions = np.array([[1.8, 4.2], [3.2, 3.1], [5.0, 1.8], [6.6, 4.3], [8.0, 3.25], [8.4, 1.4]])
    velocities = np.array([[0.3, -0.2], [-0.2, 0.25], [0.3, 0.3], [-0.25, -0.15], [0.2, 0.25], [-0.3, 0.2]])
    radii = np.array([0.8, 0.75, 0.85, 0.75, 0.85, 0.8])
    return positions, velocities, radii


RADII = six_particles()[2]
ALL_PAIRS = np.column_stack(np.triu_indices(len(RADII), 1))
SIX = collisim.World(*six_particles(), box=BOX)


def boxes(state):
    """The boxes the engine's broad phase tests in this state: each disc's bounds, grown by the
    little it could move in a step (its speculative margin)."""
    return bounding_boxes(SIX, state.positions, state.velocities, fps=60)


def plural(count, word, many=None):
    return f"{count} {word if count == 1 else many or word + 's'}"


def names(bodies):
    return ", ".join(NAMES[b] for b in bodies)


def chapter(method, title, items, steps, lines=(2, 0), side=0.0, pace=None, seconds=AFTER):
    """One broad phase's chapter: its world simulated with that broad phase, frozen at KEY while
    the build plays, then run on for `seconds`."""
    positions, velocities, radii = six_particles()
    world = collisim.World(positions=positions, velocities=velocities, radii=radii, box=BOX, colors=COLORS)
    explainer = Explainer(items, fade=0.15, lines=lines, side=side, clock="video")
    pace = pace or Pace(Freeze(KEY, steps.freeze_end - KEY))
    settings = collisim.RenderSettings(hud=False, flash=True, explainer=explainer, pace=pace)
    scene = collisim.Scene(world=world, fps=60, seconds=seconds, broadphase=method, render=settings)
    return collisim.Scene(panels=[collisim.Panel(scene, title)], fps=60, seconds=seconds)


def candidates_caption(title):
    def text(state):
        return f"{title}: {plural(state.candidates, 'candidate pair')} of {len(ALL_PAIRS)}"
    return text


# --- brute force -----------------------------------------------------------------------------

BRUTE = Steps(1.0, len(ALL_PAIRS), 0.3, HOLD)


def brute_caption(state):
    k = BRUTE.at(state)
    if k < 0:
        return ""
    if not BRUTE.built(state):
        a, b = ALL_PAIRS[k]
        return f"testing pair {k + 1} of {len(ALL_PAIRS)}: {NAMES[a]} and {NAMES[b]}"
    return (f"brute force tests all {len(ALL_PAIRS)} pairs, every frame; "
            f"{plural(state.candidates, 'pair')} of boxes overlap")


def brute_figure(canvas, rect, view, state, unit):
    k = BRUTE.at(state)
    tested = ALL_PAIRS if BRUTE.built(state) else ALL_PAIRS[:k + 1]
    draw.pair_lines(canvas, view, state.positions, tested, palette.DIM_TEXT, draw.width(unit, 0.5))
    if 0 <= k and not BRUTE.built(state):
        draw.pair_lines(canvas, view, state.positions, ALL_PAIRS[k:k + 1], palette.HIGHLIGHT, draw.width(unit, 1.25))
    if BRUTE.built(state):
        draw.pair_lines(canvas, view, state.positions, describe("brute", *boxes(state))["pairs"], palette.HIGHLIGHT,
                        draw.width(unit, 1.25))


def brute_chapter():
    items = [Caption(r"brute force: test every pair, every frame: $\frac{n\,(n-1)}{2}$ pairs for $n$ particles",
                     0.0, None, "top"),
             Caption(brute_caption, 0.0, None, "top", 1),
             Figure(brute_figure, 0.0, None, "box")]
    return chapter("brute", "brute force", items, BRUTE)


# --- sweep and prune -------------------------------------------------------------------------

SWEEP = Steps(1.5, len(RADII), 1.8, HOLD)


def sweep_step(info, k):
    """At step k of the sweep: the box taken, the active intervals it meets, the pairs the
    broad phase reported so far, and those it reported at this step."""
    order, rank = info["order"], np.argsort(info["order"])
    body = int(order[k])
    met = [j for j in info["active_steps"][k] if j != body]
    pairs = [tuple(p) for p in info["pairs"] if max(rank[p[0]], rank[p[1]]) <= k]
    now = [p for p in pairs if body in p]
    return body, met, pairs, now


def sweep_caption(state):
    k = SWEEP.at(state)
    if SWEEP.built(state):
        return candidates_caption("sweep and prune")(state)
    if k < 0:
        return ""
    info = describe("sweep_prune", *boxes(state))
    body, met, pairs, now = sweep_step(info, k)
    head = f"{k + 1} of {len(RADII)}: {NAMES[body]}"
    if not met:
        what = "meets no active interval: the active list restarts with it"
    else:
        what = f"meets {names(met)} on {'xy'[info['axis']]}: {plural(len(met), 'possible collision')} reported"
    return f"{head} {what} ({plural(len(pairs), 'pair')} so far)"


def sweep_intro(state):
    axis = "xy"[describe("sweep_prune", *boxes(state))["axis"]]
    return (f"sweep and prune: sort by the left end on {axis}; each active interval "
            f"the next one meets is a possible collision")


def sweep_lanes(canvas, rect, view, state, unit):
    info = describe("sweep_prune", *boxes(state))
    k = SWEEP.at(state)
    if SWEEP.built(state) or k < 0:
        shown = len(RADII) if SWEEP.built(state) else 0
        draw.sweep_lanes(canvas, rect, view, info["intervals"], info["order"], shown, range(len(RADII)), None,
                         COLORS, unit, outline=False)
        return
    draw.sweep_lanes(canvas, rect, view, info["intervals"], info["order"], k + 1, info["active_steps"][k],
                     int(info["order"][k]), COLORS, unit)


def sweep_figure(canvas, rect, view, state, unit):
    info = describe("sweep_prune", *boxes(state))
    k = SWEEP.at(state)
    if SWEEP.built(state) or k < 0:
        pairs = info["pairs"] if SWEEP.built(state) else []
        draw.pair_lines(canvas, view, state.positions, pairs, palette.HIGHLIGHT, draw.width(unit, 1.25))
        return
    body, met, pairs, now = sweep_step(info, k)
    x = info["intervals"][body, 0]
    draw.raster.draw_lines(canvas, view, [[x, BOX[1]]], [[x, BOX[3]]], palette.HIGHLIGHT, draw.width(unit, 0.5))
    draw.rings(canvas, view, state.positions, RADII, met, palette.DIM_TEXT, unit)
    draw.rings(canvas, view, state.positions, RADII, [body], palette.HIGHLIGHT, unit, 1.25)
    draw.pair_lines(canvas, view, state.positions, pairs, palette.HIGHLIGHT, draw.width(unit, 1.25))


def sweep_chapter():
    items = [Caption(sweep_intro, 0.0, None, "top"),
             Caption(sweep_caption, 0.0, None, "top", 1),
             Figure(sweep_lanes, 0.0, None, "bottom"),
             Figure(sweep_figure, 0.0, None, "box")]
    return chapter("sweep_prune", "sweep and prune", items, SWEEP, lines=(2, 3))


# --- uniform grid ----------------------------------------------------------------------------

GRID = Steps(1.5, len(RADII), 1.2, 4.0)
ENGINE_GRID = box_grid(BOX, RADII)         # the grid the engine keeps for this world
CHART_SIZES = (0.6, 0.8, 1.0, 1.3, 1.6, 2.0, 2.5, 3.2, 4.0, 5.0, 6.5, 10.0)


def grid_of(cell_size) -> GridState:
    """The engine's grid over the box at another cell size (the layout box_grid makes)."""
    width, height = BOX[2] - BOX[0], BOX[3] - BOX[1]
    return GridState(np.array(BOX[:2]), 1.0 / cell_size, int(width // cell_size) + 1, int(height // cell_size) + 1)


def grid_numbers(state, grid=ENGINE_GRID):
    """The engine's binning of this frame: boxes per cell, the pair tests it leads to (pairs
    sharing a cell), and the bytes of its two arrays (cell starts and entries)."""
    members, memory = draw.cell_members(*boxes(state), grid)
    counts = np.array([len(m) for m in members])
    tests = int(sum(c * (c - 1) // 2 for c in counts))
    return members, counts, tests, int(memory)


def grid_intro(state):
    size = 1.0 / ENGINE_GRID.cells_per_unit
    return (f"uniform grid: {ENGINE_GRID.nx} x {ENGINE_GRID.ny} cells of side {size:.1f}; "
            f"each particle goes into every cell its box touches")


def grid_caption(state):
    k = GRID.at(state)
    members, counts, tests, memory = grid_numbers(state)
    if GRID.built(state):
        return (f"only particles sharing a cell are tested: {plural(tests, 'pair test')}, "
                f"{plural(state.candidates, 'candidate pair')} of {len(ALL_PAIRS)}; the cells take {memory} bytes")
    if k < 0:
        return ""
    cells = sum(k in m for m in members)
    return f"{k + 1} of {len(RADII)}: {NAMES[k]} goes into {plural(cells, 'cell')}; the tags count each cell's particles"


def grid_figure(canvas, rect, view, state, unit):
    k = len(RADII) - 1 if GRID.built(state) else GRID.at(state)
    draw.grid_lines(canvas, view, BOX, ENGINE_GRID, unit)
    members, _ = draw.cell_members(*boxes(state), ENGINE_GRID)
    filed = np.array([int(np.sum(m <= k)) for m in members])
    if 0 <= k and not GRID.built(state):
        draw.rings(canvas, view, state.positions, RADII, [k], palette.HIGHLIGHT, unit, 1.25)
    if GRID.built(state):
        shared = [tuple(p) for p in ALL_PAIRS if any(p[0] in m and p[1] in m for m in members)]
        draw.pair_lines(canvas, view, state.positions, shared, palette.DIM_TEXT, draw.width(unit, 0.5))
        draw.pair_lines(canvas, view, state.positions, describe("grid", *boxes(state))["pairs"], palette.HIGHLIGHT,
                        draw.width(unit, 1.25))
    draw.cell_counts(canvas, view, BOX, ENGINE_GRID, filed, state.positions, RADII, unit)


def grid_chart(state):
    """Memory and pair tests of this frame's binning at other cell sizes, drawn once."""
    found = [grid_numbers(state, grid_of(size)) for size in CHART_SIZES]
    return draw.grid_chart(CHART_SIZES, [f[3] for f in found], [f[2] for f in found],
                           1.0 / ENGINE_GRID.cells_per_unit, (440, 620))


def grid_chapter():
    items = [Caption(grid_intro, 0.0, None, "top"),
             Caption(grid_caption, 0.0, None, "top", 1),
             Caption("small cells: fewer tests, more memory; large cells: the reverse", GRID.end, None, "top", 2),
             Figure(grid_figure, 0.0, None, "box"),
             Figure(image_figure(grid_chart), GRID.end, None, "side")]
    return chapter("grid", "uniform grid", items, GRID, lines=(3, 0), side=0.3)


# --- kd-tree ---------------------------------------------------------------------------------

def kd_splits(state):
    """The tree's splits, level by level (the order the video draws them)."""
    splits = describe("kdtree", *boxes(state), **TREE_OPTIONS)["splits"]
    return sorted(splits, key=lambda split: split[4])


def kd_split_count():
    positions, velocities, _ = six_particles()   # the frame at KEY: no wall or pair is met before it
    lo, hi = positions + KEY * velocities - RADII[:, None], positions + KEY * velocities + RADII[:, None]
    return len(describe("kdtree", lo, hi, **TREE_OPTIONS)["splits"])


KD = Steps(1.5, kd_split_count(), 1.6, 4.0)


def kd_caption(state):
    k = KD.at(state)
    if KD.live(state):
        return candidates_caption("kd-tree")(state)
    if KD.built(state):
        leaves = [leaf for leaf in describe("kdtree", *boxes(state), **TREE_OPTIONS)["leaves"] if len(leaf) > 1]
        return (f"leaves of 2 or more: {' | '.join(names(leaf) for leaf in leaves)}; "
                f"their overlapping boxes: {plural(state.candidates, 'candidate pair')}")
    if k < 0:
        return ""
    axis, value, _, _, depth = kd_splits(state)[k]
    return f"split {k + 1} of {KD.count}: the median on {'xy'[axis]}, at {'xy'[axis]} = {value:.2f} (depth {depth})"


def kd_figure(canvas, rect, view, state, unit):
    splits = kd_splits(state)
    shown = len(splits) if KD.built(state) else KD.at(state) + 1
    lo, hi = boxes(state)
    region_lo, region_hi = lo.min(axis=0), hi.max(axis=0)
    draw.raster.draw_rects(canvas, view, [region_lo], [region_hi], palette.DIM_TEXT, draw.width(unit, 0.5))
    draw.kd_splits(canvas, view, splits, shown, unit, newest=not KD.built(state))
    if KD.built(state):
        leaves = describe("kdtree", lo, hi, **TREE_OPTIONS)["leaves"]
        crowded = sorted({int(b) for leaf in leaves if len(leaf) > 1 for b in leaf})
        draw.rings(canvas, view, state.positions, RADII, crowded, palette.DIM_TEXT, unit)
        draw.pair_lines(canvas, view, state.positions, describe("kdtree", lo, hi)["pairs"], palette.HIGHLIGHT,
                        draw.width(unit, 1.25))


def kd_chapter():
    items = [Caption("kd-tree: split at the median of the centres; repeat on each side on the other axis "
                     "(x, then y, then x, ...)", 0.0, None, "top"),
             Caption(kd_caption, 0.0, None, "top", 1),
             Caption("stop at one particle, or when no median split leaves both sides smaller "
                     "(straddlers go to both)", KD.end, None, "top", 2),
             Figure(kd_figure, 0.0, None, "box")]
    return chapter("kdtree", "kd-tree", items, KD, lines=(3, 0))


# --- bounding volume hierarchy ---------------------------------------------------------------

def bvh_at_key():
    positions, velocities, _ = six_particles()
    lo, hi = positions + KEY * velocities - RADII[:, None], positions + KEY * velocities + RADII[:, None]
    info = describe("bvh", lo, hi, **TREE_OPTIONS)
    return max(node[2] for node in info["nodes"]) + 1, len(info["pairs"])


LEVELS, BVH_PAIRS = bvh_at_key()
BVH = Steps(1.5, LEVELS + BVH_PAIRS, 1.8, HOLD)


def leaf_of(info):
    """The node index of each body's leaf."""
    leaf_nodes = [k for k, node in enumerate(info["nodes"]) if node[3]]
    return {int(b): node for node, members in zip(leaf_nodes, info["leaves"]) for b in members}


def bvh_caption(state):
    k = BVH.at(state)
    if BVH.built(state):
        return candidates_caption("bounding volume hierarchy")(state)
    if k < 0:
        return ""
    info = describe("bvh", *boxes(state), **TREE_OPTIONS)
    if k < LEVELS:
        count = sum(node[2] == k for node in info["nodes"])
        return f"level {k}: {plural(count, 'box', 'boxes')}, each split in half at the median particle along its wider axis"
    j = k - LEVELS
    a, b = info["pairs"][j]
    return (f"traversal: {NAMES[a]}'s and {NAMES[b]}'s leaf boxes overlap: candidate pair {j + 1} "
            f"of {len(info['pairs'])}; boxes that miss are never opened")


def bvh_figure(canvas, rect, view, state, unit):
    info = describe("bvh", *boxes(state), **TREE_OPTIONS)
    k = BVH.at(state)
    depth = LEVELS - 1 if BVH.built(state) or k >= LEVELS else k
    if k < 0 and not BVH.built(state):
        return
    lit = []
    if LEVELS <= k and not BVH.built(state):
        leaf = leaf_of(info)
        lit = [leaf[int(b)] for b in info["pairs"][k - LEVELS]]
    draw.bvh_boxes(canvas, view, info["nodes"], depth, lit, unit, newest=k < LEVELS and not BVH.built(state))
    if BVH.built(state) or k >= LEVELS:
        done = info["pairs"] if BVH.built(state) else info["pairs"][:k - LEVELS + 1]
        draw.pair_lines(canvas, view, state.positions, done, palette.HIGHLIGHT, draw.width(unit, 1.25))


def bvh_chapter():
    items = [Caption("BVH: split the particles, not space; a tight box around each half (boxes may overlap)",
                     0.0, None, "top"),
             Caption(bvh_caption, 0.0, None, "top", 1),
             Figure(bvh_figure, 0.0, None, "box")]
    return chapter("bvh", "bounding volume hierarchy", items, BVH)


# --- the narrow phase ------------------------------------------------------------------------

FIRST_TOUCH = 0.35            # the first pair collision the engine finds (pink and orange; tested)
NARROW_PACE = Pace(Slow(0.15, FIRST_TOUCH, 0.2), Freeze(FIRST_TOUCH, 3.0), Slow(FIRST_TOUCH, 0.6, 0.2))


def touching_now(state):
    """The pairs the engine found touching in the step that ended at this sample (its PAIR events)."""
    step = state.events.between(state.time - 1e-9, state.time + 1e-9)   # found by bisection
    pairs = step.kind == PAIR
    return np.column_stack([step.i[pairs], step.j[pairs]])


def narrow_caption(state):
    """The engine's counts for this sample: its candidates and the pairs that touched."""
    return (f"narrow phase: {plural(state.pair_collisions, 'pair')} of "
            f"{plural(state.candidates, 'candidate')} touched")


def narrow_figure(canvas, rect, view, state, unit):
    pairs = describe("sweep_prune", *boxes(state))["pairs"]   # the panel's broad phase: its candidates
    draw.pair_lines(canvas, view, state.positions, pairs, palette.DIM_TEXT, draw.width(unit, 0.75))
    draw.pair_lines(canvas, view, state.positions, touching_now(state), palette.HIGHLIGHT, draw.width(unit, 2.0))


def narrow_panel():
    positions, velocities, radii = six_particles()
    world = collisim.World(positions=positions, velocities=velocities, radii=radii, box=BOX, colors=COLORS)
    items = [Caption(r"then the narrow phase tests each of sweep and prune's candidates exactly: touching when "
                     r"$|p_i - p_j| \leq r_i + r_j$", 0.0, None, "top"),
             Caption(narrow_caption, 0.0, None, "top", 1),
             Figure(narrow_figure, 0.0, None, "box")]
    settings = collisim.RenderSettings(hud=False, flash=True, pace=NARROW_PACE,
                                       explainer=Explainer(items, fade=0.0, lines=2))
    scene = collisim.Scene(world=world, fps=60, seconds=6.0, broadphase="sweep_prune", render=settings)
    return collisim.Panel(scene, "the narrow phase")


def narrow_chapter():
    return collisim.Scene(panels=[narrow_panel()], fps=60, seconds=6.0)


def scene() -> collisim.Scene:
    chapters = [brute_chapter(), sweep_chapter(), grid_chapter(), kd_chapter(), bvh_chapter(), narrow_chapter()]
    return collisim.Scene(chapters=chapters, fps=60,
                          seconds=sum(collisim.pipeline.video_seconds(c) for c in chapters))
