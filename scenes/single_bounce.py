"""One particle under gravity bouncing along the edges of a box: the update, the detection test and the response, step by step."""
import numpy as np

import collisim
from collisim.core.kinds import WALL
from collisim.render.explain import Arrow, Caption, Explainer, Note

RADIUS = 0.45
BOX = (0.0, 0.0, 16.0, 9.0)
E = 1.0                # elastic: the apex stays the same bounce after bounce


def first_bounce(state):
    """When the engine found the first wall contact (None before it happens)."""
    hits = state.events.time[state.events.kind == WALL]
    return float(hits[0]) if len(hits) else None


def after_first_bounce(delay):
    return lambda state: None if first_bounce(state) is None else first_bounce(state) + delay


def extreme_point(state):
    """The particle's lowest point: the one the floor test looks at."""
    return state.positions[0] - [0.0, RADIUS]


def velocity_tip(state):
    """Where the particle would be 0.25 s later, kept inside the box."""
    return np.clip(state.positions[0] + 0.25 * state.velocities[0], BOX[:2], BOX[2:])


def bounce_count(state):
    """The engine's running count (with one body every collision is a wall contact)."""
    return f"wall contacts found by the engine so far: {state.total_collisions}"


def explainer() -> Explainer:
    return Explainer([
        Caption(r"each frame: $p \leftarrow p + v\,\Delta t + \frac{1}{2}\,a\,\Delta t^2$,  "
                r"$v \leftarrow v + a\,\Delta t$   (exact for constant $a$)", 0.0, 3.0, "top"),
        Caption(r"the velocity arrow shows where the particle would be $0.25$ s later", 0.5, 3.0, "top", 1),
        Note("extreme point: the lowest point, $y - r$", extreme_point, 0.8, after_first_bounce(0.8), gap=RADIUS),
        Caption(r"detection: a wall is hit when the extreme point passes it:  $y - r \leq y_{min}$",
                after_first_bounce(-0.6), after_first_bounce(3.0), "bottom"),
        Caption(rf"response: $v_y \to -e\,v_y$ with $e = {E:g}$, only while moving into the wall; "
                r"the overshoot is reflected back inside", after_first_bounce(0.0), after_first_bounce(3.5),
                "bottom", 1),
        Arrow(lambda s: s.positions[0], velocity_tip, 0.5),
        Caption(bounce_count, after_first_bounce(3.5), np.inf, "bottom"),
        Caption(r"with $e = 1$ each bounce keeps the energy: $\frac{1}{2} m v^2 + m g y$ stays the same, "
                r"so does the apex", after_first_bounce(4.0), np.inf, "bottom", 1),   # after the line's fade
    ])


def scene() -> collisim.Scene:
    world = collisim.World(positions=[[1.5, 6.5]], velocities=[[3.2, 1.0]], radii=RADIUS, box=BOX,
                           gravity=(0.0, -9.8), restitution=E)
    return collisim.Scene(world=world, fps=60, seconds=8.0, method="discrete",
                          render=collisim.RenderSettings(trails=90, explainer=explainer()))
