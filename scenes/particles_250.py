"""The video's opening shot: 250 particles of three sizes and colours in a closed box."""
import collisim
from collisim.gas import lattice_gas
from collisim.render.explain import Caption, Explainer

N = 250


def each_frame(state) -> str:
    """What the engine did for this frame, in its own numbers."""
    pairs = N * (N - 1) // 2
    return (f"each frame: move every particle, test only the {state.candidates} pairs the broad phase "
            f"reports (of {pairs:,}), bounce the {state.pair_collisions} that collide")


def scene() -> collisim.Scene:
    box = (0.0, 0.0, 32.0, 18.0)
    positions, velocities, radii = lattice_gas(N, box=box, speed=3.0, seed=7)
    world = collisim.World(positions=positions, velocities=velocities, radii=radii, box=box)
    explainer = Explainer([Caption(each_frame, 0.0, None, "bottom")])
    return collisim.Scene(world=world, fps=60, seconds=10.0, method="discrete",
                          render=collisim.RenderSettings(flash=True, explainer=explainer))
