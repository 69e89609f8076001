"""Gases for scenes and benchmarks: many particles that start apart, with random velocities."""
from __future__ import annotations

import numpy as np

THREE_SIZES = (0.22, 0.32, 0.45)
SIZE_SHARES = (0.5, 0.3, 0.2)


def lattice_gas(n: int, box=(0.0, 0.0, 32.0, 18.0), speed: float = 3.0, seed: int = 7,
                sizes=THREE_SIZES, shares=SIZE_SHARES):
    """n particles on a jittered lattice filling the box (so none overlap), with random
    directions and speeds uniform in [0.5, 1.5]·speed.

    Returns positions (n, 2), velocities (n, 2), radii (n,). Raises ValueError when the
    largest size does not fit a lattice cell.
    """
    rng = np.random.default_rng(seed)
    xmin, ymin, xmax, ymax = box
    cols = int(np.ceil(np.sqrt(n * (xmax - xmin) / (ymax - ymin))))
    rows = int(np.ceil(n / cols))
    pitch = min((xmax - xmin) / cols, (ymax - ymin) / rows)
    if 2 * max(sizes) >= pitch:
        raise ValueError(f"{n} particles of radius up to {max(sizes):g} do not fit a lattice in the box")
    ix, iy = np.divmod(np.arange(n), rows)
    radii = np.asarray(sizes)[rng.choice(len(sizes), size=n, p=shares)]
    room = np.maximum(pitch / 2 - radii - 1e-3 * pitch, 0.0)
    centres = np.column_stack([xmin + (ix + 0.5) * pitch, ymin + (iy + 0.5) * pitch])
    positions = centres + rng.uniform(-1, 1, (n, 2)) * room[:, None]
    angle = rng.uniform(0, 2 * np.pi, n)
    speeds = speed * rng.uniform(0.5, 1.5, n)
    velocities = np.column_stack([np.cos(angle), np.sin(angle)]) * speeds[:, None]
    return positions, velocities, radii
