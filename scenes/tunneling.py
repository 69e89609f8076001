"""Tunnelling: the video's easy remedies first (slower particles, more frames), then side by side discrete at 1 and 4 substeps misses fast collisions, ccd never does; then how ccd finds t_c."""
import numpy as np

import collisim
from collisim import palette
from collisim.core.kinds import SEGMENT
from collisim.render import raster
from collisim.render.explain import Caption, Explainer, Note
from collisim.render.pace import Freeze, Pace, Slow

RADIUS = 0.3
TRAVEL = 6 * RADIUS            # distance a particle moves per frame at 60 fps: six radii
SPEED = TRAVEL * 60
BOX = (0.0, 0.0, 10.0, 6.0)
SECONDS = 8.0
METHODS = [("discrete", 1, "discrete, 1 step a frame"), ("discrete", 4, "discrete, 4 substeps"),
           ("ccd", 1, "continuous (ccd)")]


def barrier_world(speed=SPEED):
    """Fast particles in lanes against a thin wall at x = 5 spanning the box: any crossing is a miss."""
    lanes = np.array([1.0, 2.4, 3.8, 5.2])
    angles = np.array([0.05, -0.08, 0.11, -0.03])
    velocities = speed * np.column_stack([np.cos(angles), np.sin(angles)]) * np.array([[1.0], [0.8], [0.9], [1.1]])
    positions = np.column_stack([np.array([1.2, 2.0, 2.8, 3.6]), lanes])
    return collisim.World(positions=positions, velocities=velocities, radii=RADIUS, box=BOX,
                          segments=[[5.0, 0.0, 5.0, 6.0]], colors=[palette.pick(k) for k in range(4)])


def head_on_world():
    """Pairs of equal particles meeting head-on in lanes: a swap of order is a miss."""
    lanes = np.array([1.5, 3.0, 4.5])
    left = np.column_stack([np.full(3, 2.0), lanes])
    right = np.column_stack([np.array([8.0, 7.3, 6.6]), lanes])
    velocities = np.vstack([np.tile([SPEED / 2, 0.0], (3, 1)), np.tile([-SPEED / 2, 0.0], (3, 1))])
    colors = [palette.pick(k) for k in (0, 2, 4)] + [palette.pick(k) for k in (1, 3, 5)]
    return collisim.World(positions=np.vstack([left, right]), velocities=velocities, radii=RADIUS, box=BOX,
                          colors=colors)


class MissedOnce:
    """Counts each particle (or head-on pair) the first time a method misses its collision:
    a particle that has tunnelled keeps crossing the barrier every time it comes back, and
    counting those would measure its speed, not the method. Samples arrive in order (the
    player visits every one), so remembering who missed is enough. Who missed is kept in the
    panel's memory, not here: every play of the scene (a video, then a still) starts afresh."""

    def __init__(self, crossed):
        self.crossed = crossed

    def __call__(self, before, after):
        seen = after.memory.setdefault(("missed", id(self)), set())
        new = set(np.flatnonzero(self.crossed(before, after)).tolist()) - seen
        seen |= new
        return len(new)


def barrier_crossings(before, after):
    """(n,) True for particles whose centre went from one side of the barrier to the other
    between two samples: a collision the method missed."""
    return np.sign(before.positions[:, 0] - 5.0) != np.sign(after.positions[:, 0] - 5.0)


def pair_swaps(before, after):
    """(n/2,) True for head-on pairs (particle k and k + n) whose left-right order swapped."""
    n = len(before.positions) // 2
    order = lambda state: np.sign(state.positions[n:, 0] - state.positions[:n, 0])  # noqa: E731
    return order(before) != order(after)


def counter(label):
    def text(state):
        return f"missed {label}: {state.counters['missed']}"
    return Explainer([Caption(text, 0.0, None, "top")], fade=0.0, lines=1)


SLOW = Pace(Slow(0.0, 1.5, 0.2))   # the first 1.5 s at a fifth of real time: six radii a frame is a blur


def comparison_panels(seconds):
    panels = []
    for make_world, crossed, label in ((barrier_world, barrier_crossings, "particles (barrier)"),
                                       (head_on_world, pair_swaps, "pairs (head-on)")):
        for method, substeps, title in METHODS:
            settings = collisim.RenderSettings(trails=6, explainer=counter(label), pace=SLOW,
                                               counters={"missed": MissedOnce(crossed)})
            scene = collisim.Scene(world=make_world(), fps=60, seconds=seconds, method=method,
                                   substeps=substeps, broadphase="brute", render=settings)
            panels.append(collisim.Panel(scene, title))
    return panels


# --- the video's two easy remedies, before ccd: slower particles, more frames --------------

REMEDY = 8                      # slower by this factor, or this many times the frames a second: under a
                                # radius a frame (the fastest lane 1.1 x 6 / 8), so no step lands past the barrier
REMEDY_SECONDS = 1.5
REMEDY_PACE = Pace(Slow(0.0, 1.0, 0.25))
# (speed, frames a second, title): each moves 6, 0.75 and 0.75 radii a frame
REMEDIES = [(SPEED, 60, "too fast: 6 radii a frame"),
            (SPEED / REMEDY, 60, f"remedy 1, slower: {TRAVEL / REMEDY / RADIUS:g} radii a frame"),
            (SPEED, 60 * REMEDY, f"remedy 2, more frames: {60 * REMEDY} a second")]


def remedies_chapter():
    """The video's first two solutions on the barrier, discrete, one step a frame: a slower
    particle, or more frames a second, moves less than its diameter a frame and is caught."""
    panels = []
    for speed, fps, title in REMEDIES:
        settings = collisim.RenderSettings(trails=6, explainer=counter("particles (barrier)"), pace=REMEDY_PACE,
                                           counters={"missed": MissedOnce(barrier_crossings)})
        scene = collisim.Scene(world=barrier_world(speed), fps=fps, seconds=REMEDY_SECONDS, method="discrete",
                               broadphase="brute", render=settings)
        panels.append(collisim.Panel(scene, title))
    return collisim.Scene(panels=panels, fps=60, seconds=REMEDY_SECONDS)


# --- the explanation: the straight path between two frames, t_c, the reflected path --------

T_C = 0.23                     # the video's example: the collision happens 23 % into the frame
EXPLAIN_FPS = 1                # one simulated frame a second, so each frame is visible as a jump
FLOOR = 1.0
BIG = 0.9                      # a large particle, for clarity


def explanation_world():
    """A particle that, between frame 0 and frame 1, would cross a thin floor at t = 0.23."""
    velocity = np.array([1.6, -4.0])
    start = np.array([1.5, FLOOR + BIG - velocity[1] * T_C])
    return collisim.World(positions=[start], velocities=[velocity], radii=BIG, box=(0.0, -3.5, 9.0, 6.0),
                          segments=[[0.0, FLOOR, 9.0, FLOOR]])


def explanation_overlay(world):
    """The paths: where discrete motion puts the particle, and where ccd does."""
    p0 = world.positions[0].copy()
    v = world.velocities[0]
    p1, pc = p0 + v, p0 + T_C * v
    reflected = pc + (1 - T_C) * v * np.array([1.0, -1.0])

    def overlay(canvas, view, state):
        raster.draw_lines(canvas, view, [p0], [p1], palette.DIM_TEXT, 1)
        raster.draw_lines(canvas, view, [pc], [reflected], palette.HIGHLIGHT, 2)
        raster.draw_rings(canvas, view.to_pixels([p0, p1]), view.length([BIG, BIG]), palette.DIM_TEXT, 1)
        raster.draw_rings(canvas, view.to_pixels([pc]), view.length([BIG]), palette.HIGHLIGHT, 2)
    return overlay, (p0, p1, pc, reflected)


def derivation(points):
    """The t_c derivation, a line at a time over the frozen frame (video clock)."""
    p0, p1, pc, reflected = points
    hold = 1.0 + 0.0   # the freeze starts when frame 1 is first shown (see PACE below)
    return Explainer([
        Note(r"frame 0: $p_0$", p0, 0.0, None, gap=BIG),
        Caption(r"between frames the path is straight: $p(t) = (1 - t)\,p_0 + t\,p_1$,  $t \in [0, 1]$",
                hold + 0.5, None, "bottom"),
        Note(r"frame 1 without ccd: $p_1$, through the floor", p1, hold + 0.5, None, gap=BIG),
        Caption(r"the constraint: touching the floor, $y(t_c) = y_{floor} + r$", hold + 2.0, None, "bottom", 1),
        Caption(r"solved: $t_c = \frac{y_{floor} + r - y_0}{y_1 - y_0}$" + f"$\\, = {T_C:.2f}$",
                hold + 3.5, None, "bottom", 2),
        Note(r"$t_c$: the contact", pc, hold + 3.5, None, gap=BIG),
        Caption(lambda state: r"after $t_c$, $v_y$ flips: the path mirrors" + found_by_engine(state),
                hold + 5.0, None, "bottom", 3),
        Note(r"frame 1 with ccd: reflected", reflected, hold + 5.0, None, gap=BIG),
    ], clock="video", lines=4)


def found_by_engine(state):
    """The engine's own t_c, read from the trajectory's events once the impact has happened."""
    hits = state.events.time[state.events.kind == SEGMENT]
    return f"   (the engine found $t_c$ = {hits[0]:.4f} s)" if len(hits) else ""


EXPLAIN_PACE = Pace(Freeze(1.0, 7.0))   # hold frame 1 while the derivation appears


def explanation(seconds=3.0):
    world = explanation_world()
    overlay, points = explanation_overlay(world)
    settings = collisim.RenderSettings(overlay=overlay, explainer=derivation(points), pace=EXPLAIN_PACE,
                                       hud=True, flash=False)
    scene = collisim.Scene(world=world, fps=EXPLAIN_FPS, seconds=seconds, method="ccd", render=settings)
    return collisim.Scene(panels=[collisim.Panel(scene, "continuous detection: solve for the time of collision")],
                          fps=60, seconds=seconds)


def scene() -> collisim.Scene:
    compare = collisim.Scene(panels=comparison_panels(SECONDS), fps=60, seconds=SECONDS,
                             render=collisim.RenderSettings(layout=(2, 3)))
    chapters = [remedies_chapter(), compare, explanation()]
    return collisim.Scene(chapters=chapters, fps=60,
                          seconds=sum(collisim.pipeline.video_seconds(c) for c in chapters))
