"""A large gas kept in cell order: bodies that meet lie near each other in memory.

A gas mixes. After a few seconds bodies that touch have numbers far apart, and every pass of the
step over pairs (the grid's filing, the pairs' manifolds, the solve) reads memory at random: from
about a hundred thousand bodies, whose arrays outgrow the processor's caches, a large share of the
step (docs/benchmarks.md). So the discrete stepper of a world that qualifies (`keeps_cell_order`)
numbers its bodies anew at the start of every ORDER_FRAMES-th frame: in the
order of the cells of a fixed grid, one cell as wide as the largest body, column by column, ties
kept in the order they had. The step sees these numbers; the trajectory and the events, the
world's own (`order[k]`: the world's number of the body the step numbers k).

The renumbering depends on the run alone, not on how it is cut into blocks (it falls on frames
that are multiples of ORDER_FRAMES) nor on the broad phase (it reads positions alone), and the
step applies contacts in the canonical order of its own numbers: a run has the same bytes
whatever the blocks and the broad phase. The contacts are found again after a renumbering (one
contact phase every ORDER_FRAMES frames) and the warm-start memory follows the bodies.

Worlds of circles alone, without sleeping, segments or a map (gases in a box), of at least
ORDER_MIN bodies: with fewer, the step's arrays stay in the processor's caches whatever the
order, and the renumbering costs more than it saves.
"""
from __future__ import annotations

import numpy as np

from ..core.kinds import CIRCLE, N_WALLS, PAIR
from ..model.trajectory import Events
from ..response.warmstart import Memory

ORDER_FRAMES = 16     # frames between renumberings: a gas moves about a tenth of a radius a frame
ORDER_MIN = 100_000   # bodies (below, the renumbering cost more than it saved: docs/benchmarks.md)
MEMORY_STATICS = N_WALLS + 1   # the statics the rows of such a world number: the walls, then the (absent) map


def keeps_cell_order(world, sleep) -> bool:
    """Does the discrete stepper keep this world's bodies in cell order (the module)?"""
    return (world.n >= ORDER_MIN and sleep.on is None and len(world.segments) == 0 and world.map is None
            and bool(np.all(world.shapes == CIRCLE)))


def cell_permutation(positions, box, width: float) -> np.ndarray:
    """The bodies' new order (new number -> old): by the column, then the row, of the cell of
    `width` holding each centre, in a grid over box (4,), ties in their present order."""
    columns = np.clip(np.floor((positions[:, 0] - box[0]) / width), 0, None).astype(np.int64)
    rows = np.clip(np.floor((positions[:, 1] - box[1]) / width), 0, None).astype(np.int64)
    return np.argsort(columns * (int(rows.max()) + 1) + rows, kind="stable")


def renumber(bodies, work, memory, broad, order, box, width: float) -> tuple:
    """Number the bodies anew in cell order, in place: the state of each (bodies, and work's
    1/m and 1/I), and sweep and prune's order (kept from step to step, and
    repaired by insertion: in the new numbers it stays nearly sorted). Returns (order, memory):
    the world's number of each body, and the warm-start memory, in the new numbers."""
    new = cell_permutation(bodies.positions, box, width)   # new number -> old
    new_of_old = np.empty_like(new)
    new_of_old[new] = np.arange(len(new))
    b = bodies   # (the solver's push and shift are set for the bodies of a step's rows before use)
    for values in (b.positions, b.velocities, b.angles, b.angular_velocities, b.accelerations, b.radii, b.masses,
                   b.inertias, work.inverse_masses, work.inverse_inertias):   # (shapes: all circles)
        values[:] = values[new]
    if hasattr(broad, "axis"):
        broad.order[:] = new_of_old[broad.order]
    return order[new], renumbered_memory(memory, new_of_old, MEMORY_STATICS)


def renumbered_memory(memory: Memory, new_of_old: np.ndarray, statics: int) -> Memory:
    """The warm-start memory keyed by the bodies' new numbers (warmstart.row_key: a pair is
    keyed from its lower number)."""
    n = len(new_of_old)
    span = n + statics
    point, pair = memory.keys % 2, memory.keys // 2
    low, high = _pair_in(new_of_old, pair // span, pair % span, pair % span < n)
    keys = 2 * (low * span + high) + point
    at = np.argsort(keys, kind="stable")
    return Memory(keys[at], memory.impulses[at], memory.frictions[at])


def events_in_world_numbers(events: Events, order) -> Events:
    """The events with the world's numbers for the step's (a pair's i < j), in canonical order
    (as they are where the step keeps the world's, order None)."""
    if order is None or len(events) == 0:
        return events
    low, high = _pair_in(order, events.i, events.j, events.kind == PAIR)
    return Events.concatenate([Events(events.time, events.kind, low, high, events.impulse, events.point)])


def _pair_in(numbers, i, j, pair):
    """(i, j) in other numbers (numbers[k]: the new number of k): i, and j where `pair` says it is
    a body (else a static's number, kept), a pair's lower number first."""
    i = numbers[i]
    j = np.where(pair, numbers[np.where(pair, j, 0)], j)
    return np.where(pair, np.minimum(i, j), i), np.where(pair, np.maximum(i, j), j)


def in_world_numbers(values: np.ndarray, order) -> np.ndarray:
    """A copy of values (n, ...) by the step's numbers, as the world numbers them (order None:
    the same)."""
    if order is None:
        return values.copy()
    out = np.empty_like(values)
    out[order] = values
    return out

