"""The video's opening shot: 250 particles of three sizes and colours in a closed box."""
import numpy as np

import collisim

SIZES = np.array([0.22, 0.32, 0.45])   # three radii, three colours


def lattice_gas(n=250, box=(0.0, 0.0, 32.0, 18.0), speed=3.0, seed=7):
    """n particles on a jittered lattice (so none overlap) with random directions and speeds."""
    rng = np.random.default_rng(seed)
    xmin, ymin, xmax, ymax = box
    cols = int(np.ceil(np.sqrt(n * (xmax - xmin) / (ymax - ymin))))
    rows = int(np.ceil(n / cols))
    pitch = min((xmax - xmin) / cols, (ymax - ymin) / rows)
    ix, iy = np.divmod(np.arange(n), rows)
    radii = SIZES[rng.choice(3, size=n, p=[0.5, 0.3, 0.2])]
    room = np.maximum(pitch / 2 - radii - 1e-3, 0.0)
    centres = np.column_stack([xmin + (ix + 0.5) * pitch, ymin + (iy + 0.5) * pitch])
    positions = centres + rng.uniform(-1, 1, (n, 2)) * room[:, None]
    angle = rng.uniform(0, 2 * np.pi, n)
    speeds = speed * rng.uniform(0.5, 1.5, n)
    velocities = np.column_stack([np.cos(angle), np.sin(angle)]) * speeds[:, None]
    return positions, velocities, radii


def scene() -> collisim.Scene:
    box = (0.0, 0.0, 32.0, 18.0)
    positions, velocities, radii = lattice_gas(box=box)
    world = collisim.World(positions=positions, velocities=velocities, radii=radii, box=box)
    return collisim.Scene(world=world, fps=60, seconds=10.0, method="discrete", broadphase="sweep_prune",
                          render=collisim.RenderSettings(flash=True))
