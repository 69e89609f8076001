"""Stacks of boxes at rest under the discrete method: do they stand, sink or walk apart?

    python benchmarks/polygon_stacks.py

Boxes 1 x 0.5, e = 0, friction 0.5, gravity 9.81, one substep. Three cases, one line each:

* a column of 6 on a horizontal segment (y = 1) at 30 fps for 4 s: the bottom box's centre
  rests at 1.25; how low it went, and the largest speed at the end;
* columns of 16, each box shifted by up to 0.05 and tilted by up to 0.01 rad (seeds 0-5), at
  60 fps for 5 s: how much wider each column spread from where it started;
* a column of 20 at 60 fps for 5 s: its spread and the largest speed at the end.

Before the raised end of a tilted face was kept as a speculative point (narrowphase/polygons.py),
the first sank to 1.14 still moving at 0.72, the second spread by 0.020-0.248, the third by 0.87
still moving at 0.28.
"""
import numpy as np

import collisim
from collisim.shapes import box

H = 0.5


def run(positions, angles=None, segments=None, fps=60, seconds=5.0, top=12.0):
    n = len(positions)
    world = collisim.World(positions, polygons=[box(1.0, H)] * n, angles=angles, box=(0.0, 0.0, 10.0, top),
                           gravity=(0.0, -9.81), restitution=0.0, friction=0.5, segments=segments)
    return collisim.simulate(collisim.Scene(world=world, fps=fps, seconds=seconds))


def column_on_a_segment() -> str:
    t = run([(5.0, 1.0 + H / 2 + k * H * 1.001) for k in range(6)], angles=0.0, segments=[[1.0, 1.0, 9.0, 1.0]], fps=30,
            seconds=4.0, top=10.0)
    return (f"6 on a segment, 30 fps: bottom centre at least {t.positions[:, 0, 1].min():.4f} (rests at 1.25), "
            f"speed at the end {np.abs(t.velocities[-1]).max():.3g}")


def tilted_columns() -> str:
    spreads = []
    for seed in range(6):
        rng = np.random.default_rng(seed)
        positions = [(5.0 + rng.uniform(-0.05, 0.05), 0.01 + H / 2 + k * (H * 1.001 + 0.01)) for k in range(16)]
        t = run(positions, angles=rng.uniform(-0.01, 0.01, 16))
        spreads.append(np.ptp(t.positions[-1, :, 0]) - np.ptp(t.positions[0, :, 0]))
    return "16 tilted, 60 fps, seeds 0-5: spread grew by " + ", ".join(f"{s:.3f}" for s in spreads)


def tall_column() -> str:
    t = run([(5.0, H / 2 + k * H * 1.001) for k in range(20)], angles=0.0)
    return (f"20 in a column, 60 fps: spread {np.ptp(t.positions[-1, :, 0]):.3f}, "
            f"speed at the end {np.abs(t.velocities[-1]).max():.3g}")


if __name__ == "__main__":
    for case in (column_on_a_segment, tilted_columns, tall_column):
        print(case(), flush=True)
