"""Warm starting: each resting contact starts its solve from the impulse it had the step before.

A body resting in a pile is pressed by about the same impulse every step (its weight and the
weight above it, times dt). Sequential impulses pass that weight down one contact per sweep, so
a solve started from zero would need as many sweeps as the pile is high; started from last
step's impulses it is already solved, and the sweeps only correct what changed (Box2D,
Chipmunk).

The memory is keyed by contact, not by row number — the pair (i, j), or body i and a wall — so
a contact finds its impulse whatever other contacts came or went. It is carried from step to
step and from block to block of frames (engine/discrete.py), so a run streamed in blocks of any
size gives the same bytes. Impacts are not remembered: an impact is new, and starting the next
step from its impulse would push apart bodies that are already separating.
"""
from collections import namedtuple

import numpy as np

from ..core.arrays import stable_order
from ..core.compiling import compiled, constructor, inlined, kernel
from ..core.kinds import N_WALLS
from .rows import was_impact

Memory = namedtuple("Memory", ["keys", "impulses", "frictions"])
Memory.__doc__ = """Last step's impulses of its resting contacts: keys (k,) int64 ascending (row_key)
and their accumulated normal and friction impulses (k,)."""


@constructor
def no_memory():
    return Memory(np.empty(0, np.int64), np.empty(0), np.empty(0))


@inlined
def row_key(rows, r, n, statics=N_WALLS):
    """A number naming row r's contact point among n bodies and `statics` walls and segments, the
    same from step to step: the pair (i, j) or body i and a wall or segment (rows.wall), and the
    point's number in their manifold."""
    other = rows.j[r] if rows.j[r] >= 0 else n + rows.wall[r]
    return 2 * (rows.i[r] * (n + statics) + other) + rows.feature[r]


@kernel
def key_bodies(key, n, statics=N_WALLS):
    """The contact row_key names: (i, other), other being body j, or n + the wall or segment."""
    return (key // 2) // (n + statics), (key // 2) % (n + statics)


@compiled
def remember(rows, count, n, statics=N_WALLS):
    """The impulses of this step's pressed rows that were not impacts (rows.was_impact)."""
    keys, impulses, frictions = np.empty(count, np.int64), np.empty(count), np.empty(count)
    k = 0
    for r in range(count):
        if not was_impact(rows, r) and rows.impulse[r] > 0.0:
            keys[k], impulses[k], frictions[k] = row_key(rows, r, n, statics), rows.impulse[r], rows.friction[r]
            k += 1
    order = stable_order(keys[:k])   # rows are in canonical order, but pairs and walls interleave keys
    return Memory(keys[:k][order], impulses[:k][order], frictions[:k][order])


@kernel
def recall(rows, count, memory, n, statics=N_WALLS):
    """Each row's starting impulse: what its contact had last step, 0 if it had none. The rows'
    keys mostly ascend as the memory's do: a row looks first among the few keys after the one
    the row before found (a pile's rows find theirs there), then by binary search."""
    keys = memory.keys
    size, hint = keys.shape[0], 0
    for r in range(count):
        rows.impulse[r], rows.friction[r] = 0.0, 0.0
        if size == 0:
            continue
        key = row_key(rows, r, n, statics)
        at, stop = hint, min(hint + 4, size)
        while at < stop and keys[at] < key:
            at += 1
        if at == stop or (at == hint and at > 0 and keys[at - 1] >= key):   # not within the few
            at, high = 0, size   # the first key >= key, by halves (np.searchsorted's answer, without
            while at < high:     # compiling numba's own: 0.4 s of a first run)
                middle = (at + high) // 2
                if keys[middle] < key:
                    at = middle + 1
                else:
                    high = middle
        if at < size and keys[at] == key:
            rows.impulse[r], rows.friction[r] = memory.impulses[at], memory.frictions[at]
            hint = at + 1
