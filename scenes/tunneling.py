"""Tunnelling side by side: discrete at 1 and 4 substeps misses fast collisions, ccd never does; then how ccd finds t_c."""
import numpy as np

import collisim
from collisim import palette
from collisim.model.kinds import SEGMENT
from collisim.render import raster

RADIUS = 0.3
TRAVEL = 6 * RADIUS            # distance a particle moves per frame at 60 fps: six radii
SPEED = TRAVEL * 60
BOX = (0.0, 0.0, 10.0, 6.0)
SECONDS = 8.0
METHODS = [("discrete", 1, "discrete, 1 step a frame"), ("discrete", 4, "discrete, 4 substeps"),
           ("ccd", 1, "continuous (ccd)")]


def barrier_world():
    """Fast particles in lanes against a thin wall at x = 5 spanning the box: any crossing is a miss."""
    lanes = np.array([1.0, 2.4, 3.8, 5.2])
    angles = np.array([0.05, -0.08, 0.11, -0.03])
    velocities = SPEED * np.column_stack([np.cos(angles), np.sin(angles)]) * np.array([[1.0], [0.8], [0.9], [1.1]])
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


def barrier_crossings(before, after):
    """Particles whose centre went from one side of the barrier to the other between two
    samples: each is a collision the method missed."""
    return int(np.sum(np.sign(before.positions[:, 0] - 5.0) != np.sign(after.positions[:, 0] - 5.0)))


def pair_swaps(before, after):
    """Head-on pairs (particle k and k + n) whose left-right order swapped between two samples."""
    n = len(before.positions) // 2
    order = lambda state: np.sign(state.positions[n:, 0] - state.positions[:n, 0])  # noqa: E731
    return int(np.sum(order(before) != order(after)))


def counter(label):
    def overlay(canvas, view, state):
        x, y = view.to_pixels([BOX[0], BOX[3]])
        count = state.counters["missed"]
        color = palette.HIGHLIGHT if count else palette.PARTICLES[2]
        raster.draw_text(canvas, f"missed {label}: {count}", (x + 8, y + 20), scale=0.45, color_rgb=color)
    return overlay


def comparison_panels(seconds):
    panels = []
    for make_world, count_missed, label in ((barrier_world, barrier_crossings, "barrier hits"),
                                            (head_on_world, pair_swaps, "pair collisions")):
        for method, substeps, title in METHODS:
            settings = collisim.RenderSettings(trails=6, overlay=counter(label), counters={"missed": count_missed})
            scene = collisim.Scene(world=make_world(), fps=60, seconds=seconds, method=method,
                                   substeps=substeps, broadphase="brute", render=settings)
            panels.append(collisim.Panel(scene, title))
    return panels


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
    p0 = world.positions[0].copy()
    v = world.velocities[0]
    p1 = p0 + v                                   # where discrete motion puts it one frame later
    pc = p0 + T_C * v                             # the centre at the moment of contact
    reflected = pc + (1 - T_C) * v * np.array([1.0, -1.0])

    def overlay(canvas, view, state):
        raster.draw_lines(canvas, view, [p0], [p1], palette.DIM_TEXT, 1)
        raster.draw_lines(canvas, view, [pc], [reflected], palette.HIGHLIGHT, 2)
        raster.draw_rings(canvas, view.to_pixels([p0, p1]), view.length([BIG, BIG]), palette.DIM_TEXT, 1)
        raster.draw_rings(canvas, view.to_pixels([pc]), view.length([BIG]), palette.HIGHLIGHT, 2)
        notes = [(p0, "frame 0: p0"), (p1, "frame 1 without ccd: p1, through the floor"),
                 (pc, f"t_c = {T_C:.2f}: r above the floor"), (reflected, "frame 1 with ccd: reflected")]
        size = max(0.38, 0.5 * min(1.0, view.scale / 66))   # text shrinks with small frames
        for point, text in notes:
            x, y = view.to_pixels(point)
            raster.draw_text(canvas, text, (x + view.length(BIG * 1.15), y + 5), scale=size, color_rgb=palette.TEXT)
        for k, line in enumerate(["p(t) = (1 - t) p0 + t p1     linear interpolation over the frame",
                                  "y(t_c) = floor + r          the constraint: solve it for t_c",
                                  "after t_c, v_y flips: the path mirrors" + found_by_engine(state)]):
            x, y = view.to_pixels([0.3, -2.3 - 0.38 * k])
            raster.draw_text(canvas, line, (x, y), scale=size, color_rgb=palette.TEXT)
    return overlay


def found_by_engine(state):
    """The engine's own t_c, read from the trajectory's events once the impact has happened."""
    hits = state.events.time[state.events.kind == SEGMENT]
    return f"   (engine found t_c = {hits[0]:.4f})" if len(hits) else ""


def explanation(seconds=6.0):
    world = explanation_world()
    settings = collisim.RenderSettings(overlay=explanation_overlay(world), hud=True, flash=False)
    scene = collisim.Scene(world=world, fps=EXPLAIN_FPS, seconds=seconds, method="ccd", render=settings)
    return collisim.Scene(panels=[collisim.Panel(scene, "continuous detection: solve for the time of collision")],
                          fps=60, seconds=seconds)


def scene() -> collisim.Scene:
    compare = collisim.Scene(panels=comparison_panels(SECONDS), fps=60, seconds=SECONDS,
                             render=collisim.RenderSettings(layout=(2, 3)))
    explain = explanation()
    return collisim.Scene(chapters=[compare, explain], fps=60, seconds=compare.seconds + explain.seconds)
