"""Two particles of different masses meeting obliquely: slow motion at the impact, the line of centres and the velocity split from momentum and energy."""
import numpy as np

import collisim
from collisim.core.kinds import PAIR
from collisim.render.explain import Arrow, Caption, Explainer, Mark
from collisim.render.pace import Freeze, Pace, Slow

MEET = 1.137            # the initial state below is chosen so the two touch at t = 1.137 s
IMPACT = 69 / 60        # the first sample after they touch: the discrete step finds them there
FREEZE = 4.0            # seconds the impact is held on screen
PACE = Pace(Slow(MEET - 0.3, IMPACT, 0.125), Freeze(IMPACT, FREEZE), Slow(IMPACT, MEET + 0.3, 0.125))


def impact(state):
    """The engine's first pair collision: (time, impulse), or None before it."""
    hits = np.flatnonzero(state.events.kind == PAIR)
    return (float(state.events.time[hits[0]]), float(state.events.impulse[hits[0]])) if len(hits) else None


def line_of_centres(state):
    d = state.positions[1] - state.positions[0]
    return d / np.hypot(*d)


def conserved(world):
    """Momentum and kinetic energy before and after, from the same trajectory-read velocities."""
    def text(state):
        found = impact(state)
        if found is None:
            return ""
        (before1, before2), (after1, after2) = velocities(world, state, found[1])
        m1, m2 = world.masses
        p0, p1 = m1 * before1 + m2 * before2, m1 * after1 + m2 * after2
        e0 = 0.5 * (m1 * before1 @ before1 + m2 * before2 @ before2)
        e1 = 0.5 * (m1 * after1 @ after1 + m2 * after2 @ after2)
        return (rf"momentum ({p0[0]:.3f}, {p0[1]:.3f}) $\to$ ({p1[0]:.3f}, {p1[1]:.3f}),   "
                rf"energy {e0:.3f} $\to$ {e1:.3f}")
    return text


def velocities(world, state, impulse):
    """((v1, v2) before, (v1, v2) after) the first impact. Before: the velocities they start with,
    since nothing acts on them until they meet (no gravity, no wall reached first). After: read at
    the impact's sample, the first time it is asked (the freeze holds that sample); the answer is
    kept for the rest of the play (state.memory), since later samples have moved on (velocities
    changed by walls)."""
    if "velocities at impact" not in state.memory:
        after1, after2 = state.velocities[0].copy(), state.velocities[1].copy()
        state.memory["velocities at impact"] = (world.velocities[0].copy(), world.velocities[1].copy()), (after1, after2)
    return state.memory["velocities at impact"]


def split(world):
    """Velocities before and after the impact, read off the trajectory: the sample after the
    impact holds the velocities after it, and the logged impulse J along the line of centres n
    gives the ones before, v1 = v1' + J n / m1, v2 = v2' - J n / m2."""
    def text(state):
        found = impact(state)
        if found is None:
            return ""
        (before1, before2), (after1, after2) = velocities(world, state, found[1])
        return (rf"$v_1$: ({before1[0]:.2f}, {before1[1]:.2f}) $\to$ ({after1[0]:.2f}, {after1[1]:.2f})    "
                rf"$v_2$: ({before2[0]:.2f}, {before2[1]:.2f}) $\to$ ({after2[0]:.2f}, {after2[1]:.2f})")
    return text


def explainer(world) -> Explainer:
    m1, m2 = world.masses
    t0, slow = 0.0, PACE.video_time(MEET - 0.3)
    at_freeze = PACE.video_time(IMPACT)
    return Explainer([
        Mark((0, 1), t0, at_freeze + FREEZE, labels=(f"1: m = {m1:.2f}", f"2: m = {m2:.2f}")),
        Caption(r"two discs, masses proportional to area: $m_2 = 4\,m_1$", t0, slow, "top"),
        Caption(r"slow motion: the step that finds them touching, $|p_2 - p_1| \leq r_1 + r_2$",
                slow, at_freeze, "top"),
        Arrow(lambda s: s.positions[0], lambda s: s.positions[1], at_freeze, at_freeze + FREEZE,
              label="line of centres n", label_gap=1.2),
        Caption(r"only the part along $n$ changes: $v_1' = v_1 - \frac{2 m_2}{m_1 + m_2}"
                r"\,((v_1 - v_2)\cdot n)\,n$,  $v_2' = v_2 + \frac{2 m_1}{m_1 + m_2}\,((v_1 - v_2)\cdot n)\,n$",
                at_freeze, at_freeze + FREEZE + 3.0, "top"),
        Caption(r"from conservation of momentum, $m_1 v_1 + m_2 v_2$, and of energy, "
                r"$\frac{1}{2} m_1 |v_1|^2 + \frac{1}{2} m_2 |v_2|^2$", at_freeze + 0.8, at_freeze + FREEZE + 3.0,
                "top", 1),
        Caption(split(world), at_freeze + 1.6, None, "bottom"),
        Caption(conserved(world), at_freeze + 2.4, None, "bottom", 1),
    ], clock="video")


def scene() -> collisim.Scene:
    world = collisim.World(
        positions=[[3.0, 3.2], [12.0, 5.6]],
        velocities=[[4.0, 1.1], [-2.6, -0.4]],
        radii=[0.55, 1.1],
        box=(0.0, 0.0, 16.0, 9.0),
    )
    return collisim.Scene(
        world=world, fps=60, seconds=8.0, method="discrete",
        render=collisim.RenderSettings(trails=45, arrows=True, explainer=explainer(world), pace=PACE),
    )
