"""Does a pyramid of unit boxes stand? Box2D's large pyramid under the discrete method, beside Box2D 2.3.

    python benchmarks/pyramid_stands.py [--base 100] [--seconds 10]

The pyramid is `collisim bench polygons`'s (analysis/bench/workloads.py: pyramids(base), e = 0,
mu = 0.6, g = 10, 60 fps, one step a frame); base 100 is 5 050 boxes. Every second, for each
engine: how many boxes are more than 0.5 from where they started, the farthest, the fastest, and
how far the top box has moved up (+) or down (-). A pyramid that stands keeps the first figure at 0.
(Box2D keeps a skin of 0.01 around every polygon, so its pyramid first rises by about that a row.)
"""
import argparse

import numpy as np

import collisim
from collisim.analysis.bench.workloads import pyramids


def report(name: str, start: np.ndarray, positions: np.ndarray, velocities: np.ndarray, t: float) -> None:
    moved = np.hypot(*(positions - start).T)
    top = int(np.argmax(start[:, 1]))
    print(f"{name:10s} t={t:5.1f} s  boxes moved > 0.5: {int((moved > 0.5).sum()):5d}  farthest {moved.max():6.3f}  "
          f"fastest {np.hypot(*velocities.T).max():6.3f}  top {positions[top, 1] - start[top, 1]:+.3f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--base", type=int, default=100)
    parser.add_argument("--seconds", type=float, default=10.0)
    args = parser.parse_args()
    world, fps = pyramids(args.base), 60
    print(f"a pyramid of base {args.base}: {world.n} boxes, {args.seconds:g} s at {fps} fps")
    trajectory = collisim.simulate(collisim.Scene(world=world, fps=fps, seconds=args.seconds))
    for f in range(fps, trajectory.frames + 1, fps):
        report("collisim", trajectory.positions[0], trajectory.positions[f], trajectory.velocities[f], f / fps)
    try:
        from collisim.analysis.reference.box2d_world import Box2DWorld
    except ImportError:
        print("Box2D 2.3 is not installed (pip install box2d)")
        return
    reference = Box2DWorld(world, fps)
    for second in range(1, int(args.seconds) + 1):
        reference.step(fps)
        report("Box2D 2.3", world.positions, reference.positions, reference.velocities, float(second))


if __name__ == "__main__":
    main()
