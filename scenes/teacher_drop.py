"""A teacher's example, written from the README: a ball dropped on the floor, explained."""
import collisim
from collisim.core.kinds import WALL
from collisim.render.explain import Arrow, Caption, Explainer, Mark, Note

def first_bounce(state):          # when the engine found it; None until then
    hits = state.events.time[state.events.kind == WALL]
    return hits[0] if len(hits) else None

def scene():
    world = collisim.World(positions=[[5, 4]], velocities=[[1, 0]], radii=0.5, gravity=(0, -9.8),
                           restitution=0.8)
    explainer = Explainer([
        Caption(r"gravity: $v \leftarrow v + a\,\Delta t$ every step", 0, 2, "top"),
        Caption(r"bounce: $v_y \to -e\,v_y$", first_bounce, None, "bottom"),
        Caption(lambda s: rf"vertical speed $|v_y|$ now {abs(s.velocities[0, 1]):.2f}", 0, None, "bottom", line=1),
        Mark((0,), 0, 2),                                         # numbers body 0 beside it
        Note("lowest point", lambda s: s.positions[0] - [0, 0.5], 0, 2, gap=0.5),
        Arrow(lambda s: s.positions[0], lambda s: s.positions[0] + 0.3 * s.velocities[0]),
    ])
    return collisim.Scene(world=world, fps=60, seconds=4,
                          render=collisim.RenderSettings(explainer=explainer))
