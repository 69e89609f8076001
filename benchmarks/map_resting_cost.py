"""The cost of a pile resting on a collision map, the worst case of reading a body's contact with
the map across its width (statics/map_field.map_contact): the drop world of `collisim bench
maps` (40 circles poured into its level) at K cells a radius, 2 s at 60 fps and 4 substeps,
timed after a warm-up, best of three. Run it in two checkouts in turn to compare them:

    python benchmarks/map_resting_cost.py [K]
"""
import sys
import time

import collisim
from collisim.analysis.bench import maps


def main(cells_per_radius: float = 8.0) -> None:
    world = maps.drop_world(collision_map=maps.level_map(cells_per_radius))
    scene = collisim.Scene(world=world, fps=60, seconds=2.0, method="discrete", substeps=4)
    collisim.simulate(scene.replace(seconds=0.1))   # compile or load the kernels outside the timing
    best = float("inf")
    for _ in range(3):
        start = time.perf_counter()
        collisim.simulate(scene)
        best = min(best, time.perf_counter() - start)
    print(f"{cells_per_radius:g} cells a radius: {best:.3f} s for 2 s of {world.n} bodies")


if __name__ == "__main__":
    main(*map(float, sys.argv[1:2]))
