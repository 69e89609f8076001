"""`collisim bench segments`: what static segments cost the discrete step.

A gas of n bodies with m thin segments scattered through it, against the same gas without
them, stepped by the discrete method in the same run: the ratio is the price of the statics.
With the static index a body tests only the segments near it, so the ratio stays near 1 as m
grows; testing every body against every segment would make it grow like m.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

import collisim
from collisim.gas import lattice_gas
from collisim.narrowphase.statics import touching_segments

from ...core.files import write_text
from .broadphase import time_discrete_step


def segment_gas(n: int, m: int, seed: int = 3, length: float = 1.2) -> collisim.World:
    """About n bodies on a jittered lattice (packing about 0.1) among m random segments of
    `length`, in a square box; the bodies a segment would cut through are left out."""
    side = float(np.sqrt(n * np.pi * 0.3 ** 2 / 0.1))
    box = (0.0, 0.0, side, side)
    positions, velocities, radii = lattice_gas(n, box=box, speed=3.0, seed=seed, sizes=(0.3,), shares=(1.0,))
    rng = np.random.default_rng(seed)
    starts = rng.uniform(0.0, side, (m, 2))
    angles = rng.uniform(0.0, np.pi, m)
    ends = np.clip(starts + length * np.column_stack([np.cos(angles), np.sin(angles)]), 0.0, side)
    segments = np.column_stack([starts, ends])
    free = np.ones(len(positions), bool)
    free[touching_segments(positions, radii, segments, box)[0][:, 0]] = False
    return collisim.World(positions[free], velocities[free], radii[free], box=box, segments=segments)


def run(out_dir: Path, n: int = 18_000, m: int = 2_000, repeats: int = 3) -> dict:
    """Time both worlds in one run (seconds per frame of the discrete step, grid, median of
    repeats); write segments.json; return the figures."""
    with_segments = segment_gas(n, m)
    without = with_segments.copy(segments=None)
    plain = time_discrete_step(collisim.Scene(world=without), repeats)
    statics = time_discrete_step(collisim.Scene(world=with_segments), repeats)
    figures = {"bodies": n, "segments": m, "seconds_per_frame_without": plain,
               "seconds_per_frame_with": statics, "ratio": statics / plain}
    path = Path(out_dir) / "segments.json"
    write_text(path, json.dumps(figures, indent=2))
    figures["json"] = str(path)
    return figures
