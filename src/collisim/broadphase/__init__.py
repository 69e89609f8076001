"""Broad phase: which pairs of circles could possibly collide?

Testing every pair exactly costs n² work. The broad phase looks only at each
circle's axis-aligned bounding box and cheaply rules out pairs that cannot
touch; the narrow phase then tests the few remaining candidates exactly.
Five methods, one module each, in the order the video introduces them:

* ``brute``       — test all pairs (:mod:`.brute`);
* ``sweep_prune`` — sort along one axis and sweep (:mod:`.sweep_prune`);
* ``grid``        — bin the boxes into uniform cells (:mod:`.grid`);
* ``kdtree``      — split space at medians (:mod:`.kdtree`);
* ``bvh``         — group objects into a tree of boxes (:mod:`.bvh`).

Every method returns candidate pairs as a (k, 2) ``np.intp`` array of
``i < j``, sorted and unique, containing every pair of overlapping boxes
(touching counts). Boxes are given as ``lo, hi``: (n, 2) float64 min and max
corners.
"""

import numpy as np

from ._common import BroadPhase
from .brute import BruteForce
from .bvh import BoundingVolumeHierarchy
from .grid import UniformGrid
from .kdtree import KDTree
from .sweep_prune import SweepAndPrune

__all__ = ["METHODS", "BroadPhase", "describe", "find_pairs", "make"]

METHODS = ("brute", "sweep_prune", "grid", "kdtree", "bvh")
NAMES = METHODS

_CLASSES = {cls.name: cls for cls in (BruteForce, SweepAndPrune, UniformGrid, KDTree,
                                       BoundingVolumeHierarchy)}


def make(method: str, **options) -> BroadPhase:
    """A broad phase for `method`, to call ``.pairs(lo, hi)`` on once per frame.

    Options: grid: ``cell_size``; kdtree: ``leaf_size``, ``max_depth``;
    bvh: ``leaf_size``. Raises ValueError for an unknown method or option.
    """
    if method not in _CLASSES:
        raise ValueError(f"unknown broad phase {method!r}; choose one of: {', '.join(METHODS)}")
    cls = _CLASSES[method]
    unknown = sorted(set(options) - set(cls.OPTIONS))
    if unknown:
        valid = ", ".join(cls.OPTIONS) or "none"
        raise ValueError(f"unknown option {unknown[0]!r} for broad phase {method!r}; valid options: {valid}")
    return cls(**options)


def find_pairs(method: str, lo, hi, **options) -> np.ndarray:
    """Candidate pairs of boxes lo, hi: (n, 2) -> (k, 2) intp, i < j, sorted, unique."""
    return make(method, **options).pairs(lo, hi)


def describe(method: str, lo, hi, **options) -> dict:
    """The method's data structure for drawing a tutorial picture (see each
    class's ``describe``), always with the ``"pairs"`` it finds."""
    return make(method, **options).describe(lo, hi)
