"""Every broad phase, registered once: its name, the class that answers the protocol (pairs,
query, raycast, describe), the state the discrete step keeps for it with the kernel that finds
its candidate pairs, and the structure a ray query searches with the kernel that finds a ray's
closest body. Chipmunk's cpSpatialIndex does the same with one function table per index.

The compiled entry points `candidate_pairs(state, lo, hi)` (step.py) and
`body_ray_closest(state, bodies, ray, best)` (ray_closest.py) pick their kernel here by the
*type* of the state when their caller is compiled (numba's overload): a run compiles only the
broad phase it uses, and each choice is cached on its own.
"""
from collections import namedtuple

import numpy as np
from numba.extending import overload

from . import ray_closest as rays
from . import step
from .brute import BruteForce
from .bvh import BoundingVolumeHierarchy
from .cell_list import CellList
from .grid import UniformGrid
from .kdtree import KDTree
from .sweep_prune import SweepAndPrune

BroadPhaseKind = namedtuple("BroadPhaseKind", ["protocol", "StepState", "step_state", "pairs",
                                               "RayState", "ray_state", "closest_body"],
                            defaults=(None,) * 6)
BroadPhaseKind.__doc__ = """protocol: the BroadPhase class. StepState: the type of the discrete
step's state, step_state(world) makes it, pairs(state, lo, hi) -> candidate pairs (a plain
function, compiled inside the step). RayState: the type of the ray search's structure,
ray_state(lo, hi) makes it, closest_body(state, bodies, ray, best) -> (best, visited, tested).
ccd's cell lists answer the protocol only (engine/ccd/ keeps its own)."""

BROAD_PHASES = {
    "brute": BroadPhaseKind(BruteForce, step.BruteState, lambda world: step.BruteState(world.n), step.brute_pairs,
                            rays.BruteRays, lambda lo, hi: rays.BruteRays(len(lo)), rays.brute_ray_closest),
    "sweep_prune": BroadPhaseKind(SweepAndPrune, step.SweepState, step.sweep_state, step.sweep_pairs,
                                  rays.SweepRays, rays.sweep_rays, rays.sweep_ray_closest),
    "grid": BroadPhaseKind(UniformGrid, step.GridState, lambda world: step.box_grid(world.box, world.radii),
                           step.grid_step_pairs, rays.GridRays, rays.grid_rays, rays.grid_ray_closest),
    "kdtree": BroadPhaseKind(KDTree, step.KDTreeState, lambda world: step.KDTreeState(2, 32), step.kdtree_step_pairs,
                             rays.KDTreeRays, rays.kdtree_rays, rays.kdtree_ray_closest),
    "bvh": BroadPhaseKind(BoundingVolumeHierarchy, step.BVHState, lambda world: step.BVHState(2), step.bvh_step_pairs,
                          rays.BVHRays, rays.bvh_rays, rays.bvh_ray_closest),
    "cells": BroadPhaseKind(CellList),
}

# The broad phases a discrete run or a ray query may use, in the order the video introduces them.
NAMES = tuple(name for name, kind in BROAD_PHASES.items() if kind.pairs is not None)
# Every structure that answers the protocol: the five, and ccd's cell lists.
PROTOCOL = tuple(BROAD_PHASES)

AUTO = "auto"
BRUTE_UP_TO = 64        # bodies: up to this, testing every pair beats building anything (the
                        # polygons scene's 60 bodies: 3 us brute force, 7 us the grid)
SIZE_SPREAD = 8.0       # largest radius / median radius beyond which the grid's cells fit badly


def choose(world) -> str:
    """The broad phase `auto` picks for a world: brute force for a handful of bodies, the
    uniform grid (the fastest in `collisim bench broadphase` at every n) when the bodies have
    similar sizes, and the BVH when a few are much larger than the rest (the grid's cells are
    sized by the typical body, so a large one would be filed in many cells)."""
    if world.n <= BRUTE_UP_TO:
        return "brute"
    if world.radii.max() > SIZE_SPREAD * np.median(world.radii):
        return "bvh"
    return "grid"


def step_state(name: str, world):
    """The state the discrete step keeps for broad phase `name` (or `auto`) over `world`."""
    return BROAD_PHASES[choose(world) if name == AUTO else name].step_state(world)


def ray_state(name: str, lo, hi):
    """The structure broad phase `name` searches, built over the bodies' boxes lo, hi (n, 2),
    float64, C-contiguous. With no bodies every name gets brute force's (there is nothing to
    build a structure over, and nothing to find)."""
    return BROAD_PHASES[name if len(lo) else "brute"].ray_state(lo, hi)


_PAIRS = {kind.StepState: kind.pairs for kind in BROAD_PHASES.values() if kind.pairs is not None}
_CLOSEST = {kind.RayState: kind.closest_body for kind in BROAD_PHASES.values() if kind.pairs is not None}


@overload(step.candidate_pairs)
def _candidate_pairs(state, lo, hi):
    return _PAIRS[state.instance_class]


@overload(rays.body_ray_closest)
def _body_ray_closest(state, bodies, ray, best):
    kernel = _CLOSEST[state.instance_class]

    def impl(state, bodies, ray, best):
        return kernel(state, bodies, ray, best)
    return impl
