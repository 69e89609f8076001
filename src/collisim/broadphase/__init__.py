"""Broad phase: which pairs of circles could possibly collide?

Testing every pair exactly costs n² work. The broad phase looks only at each
circle's axis-aligned bounding box and cheaply rules out pairs that cannot
touch; the narrow phase then tests the few remaining candidates exactly.
Five broad phases (NAMES), one module each, in the order the video introduces them:

* ``brute``       — test all pairs (:mod:`.brute`);
* ``sweep_prune`` — sort along one axis and sweep (:mod:`.sweep_prune`);
* ``grid``        — bin the boxes into uniform cells (:mod:`.grid`);
* ``kdtree``      — split space at medians (:mod:`.kdtree`);
* ``bvh``         — group objects into a tree of boxes (:mod:`.bvh`).

Every one returns candidate pairs as a (k, 2) ``np.intp`` array of
``i < j``, sorted and unique, containing every pair of overlapping boxes
(touching counts). Boxes are given as ``lo, hi``: (n, 2) float64 min and max
corners.

Each also answers two more questions, in its own way:

* :func:`query` — which boxes overlap a query box? (k,) intp indices, sorted;
* :func:`raycast` — which boxes does a ray segment pass through, and how far
  along the ray does it enter each? Indices (k,) intp and t_enter (k,)
  float64, sorted by (t_enter, index).

Both report exact answers (no extra candidates), and leave in ``stats`` how
many nodes, cells or boxes it ``visited`` to find them. The discrete step calls the
pair kernels from compiled code through step.py.
"""

import numpy as np

from ._common import BroadPhase
from .registry import BROAD_PHASES, NAMES, PROTOCOL

__all__ = ["NAMES", "PROTOCOL", "BroadPhase", "describe", "find_pairs", "make", "query", "raycast"]


def make(name: str, **options) -> BroadPhase:
    """A broad phase by `name`, to call ``.pairs(lo, hi)`` on once per frame.

    Options: grid: ``cell_size``; kdtree: ``leaf_size``, ``max_depth``;
    bvh: ``leaf_size``. Raises ValueError for an unknown name or option.
    """
    if name not in BROAD_PHASES:
        raise ValueError(f"unknown broad phase {name!r}; choose one of: {', '.join(PROTOCOL)}")
    cls = BROAD_PHASES[name].protocol
    unknown = sorted(set(options) - set(cls.OPTIONS))
    if unknown:
        valid = ", ".join(cls.OPTIONS) or "none"
        raise ValueError(f"unknown option {unknown[0]!r} for broad phase {name!r}; valid options: {valid}")
    return cls(**options)


def find_pairs(name: str, lo, hi, **options) -> np.ndarray:
    """Candidate pairs of boxes lo, hi: (n, 2) -> (k, 2) intp, i < j, sorted, unique."""
    return make(name, **options).pairs(lo, hi)


def query(name: str, lo, hi, box_lo, box_hi, **options) -> np.ndarray:
    """Boxes lo, hi: (n, 2) overlapping the box box_lo, box_hi: (2,) each
    (touching counts) -> (k,) intp indices, ascending, unique."""
    return make(name, **options).query(lo, hi, box_lo, box_hi)


def raycast(name: str, lo, hi, origin, direction, max_distance,
            **options) -> tuple[np.ndarray, np.ndarray]:
    """Boxes lo, hi: (n, 2) met by the segment origin + t * u, t in
    [0, max_distance], u = direction / |direction| (origin, direction: (2,);
    max_distance >= 0, may be inf) -> indices (k,) intp and t_enter (k,)
    float64, where the ray enters each box (0 if it starts inside), sorted by
    (t_enter, index). Raises ValueError for a bad ray."""
    return make(name, **options).raycast(lo, hi, origin, direction, max_distance)


def describe(name: str, lo, hi, **options) -> dict:
    """The broad phase's data structure for drawing a tutorial picture (see each
    class's ``describe``), always with the ``"pairs"`` it finds."""
    return make(name, **options).describe(lo, hi)
