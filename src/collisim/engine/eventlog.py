"""The collision log that compiled engines append to, and its conversion to Events."""
from collections import namedtuple

import numpy as np

from ..core.arrays import stable_order
from ..core.compiling import compiled, constructor, kernel
from ..model.trajectory import Events

EventLog = namedtuple("EventLog", ["time", "kind", "i", "j", "impulse", "point", "size"])
EventLog.__doc__ = """Collisions as appended: time, impulse (c,) float64; kind (c,) int8; i, j (c,) intp;
point (c, 2); size (1,) int64 how many of the c rows are filled. Fields as in Events."""


@constructor
def new_log(capacity):
    """An empty log with room for `capacity` collisions."""
    return EventLog(np.empty(capacity), np.empty(capacity, np.int8), np.empty(capacity, np.intp),
                    np.empty(capacity, np.intp), np.empty(capacity), np.empty((capacity, 2)), np.zeros(1, np.int64))


@compiled
def with_room(log, extra):
    """The log with room for `extra` more collisions: the same one, or one with larger arrays.

    Reserve before a loop and append inside it: a log reassigned inside a loop makes numba
    count references to its seven arrays at every iteration, which costs more than the loop."""
    used = log.size[0]
    need = used + extra
    if need <= log.time.shape[0]:
        return log
    room = new_log(max(need, 2 * log.time.shape[0]))   # (arrays.grown's rule)
    # one loop over the rows, not arrays.grown for each field: that compiled a kernel for each of
    # the fields' four array types, in every first run (docs/benchmarks.md, the first run)
    for k in range(used):
        room.time[k], room.kind[k], room.i[k], room.j[k] = log.time[k], log.kind[k], log.i[k], log.j[k]
        room.impulse[k], room.point[k, 0], room.point[k, 1] = log.impulse[k], log.point[k, 0], log.point[k, 1]
    return EventLog(room.time, room.kind, room.i, room.j, room.impulse, room.point, log.size)


@kernel
def has_room(log, extra):
    """Has the log room for `extra` more collisions?"""
    return log.size[0] + extra <= log.time.shape[0]


@kernel
def append(log, t, kind, i, j, impulse, x, y):
    """Add a collision to a log that has room for it (see with_room)."""
    k = log.size[0]
    log.time[k], log.kind[k], log.i[k], log.j[k], log.impulse[k] = t, kind, i, j, impulse
    log.point[k, 0], log.point[k, 1] = x, y
    log.size[0] = k + 1


@kernel
def in_canonical_order(log):
    """Are the logged collisions in canonical (time, kind, i, j) order already (Events.in_order,
    in one pass where they were logged: a block of a world asleep logs its supports in order)?"""
    for k in range(1, log.size[0]):
        if log.time[k] != log.time[k - 1]:
            if log.time[k] < log.time[k - 1]:
                return False
        elif log.kind[k] != log.kind[k - 1]:
            if log.kind[k] < log.kind[k - 1]:
                return False
        elif log.i[k] != log.i[k - 1]:
            if log.i[k] < log.i[k - 1]:
                return False
        elif log.j[k] < log.j[k - 1]:
            return False
    return True


@compiled
def into_canonical_order(log):
    """Put the logged collisions in canonical (time, kind, i, j) order, in place, and say whether
    they are in it: the order model.trajectory.canonical_order gives (one integer key a row, the
    time's rank, kind, i and j + 1 packed, sorted stably), sorted where they were logged, so that
    Python need not sort each block (docs/benchmarks.md, polygons). Logs whose times decrease, or
    whose keys would not fit in 62 bits, are left as they are (False): Python sorts those."""
    k = log.size[0]
    if in_canonical_order(log):
        return True
    span, ranks = 1, 1
    for r in range(k):
        if log.i[r] < 0 or log.j[r] < -1 or log.kind[r] < 0 or log.kind[r] >= 8:
            return False
        span = max(span, log.i[r] + 1, log.j[r] + 2)   # i and j + 1 lie in 0 .. span - 1
        if r > 0 and log.time[r] != log.time[r - 1]:
            if log.time[r] < log.time[r - 1]:
                return False
            ranks += 1
    if float(ranks) * 8.0 * float(span) * float(span) >= 2.0 ** 62:
        return False
    keys, rank = np.empty(k, np.int64), 0
    for r in range(k):
        rank += 1 if r > 0 and log.time[r] != log.time[r - 1] else 0
        keys[r] = ((rank * 8 + log.kind[r]) * span + log.i[r]) * span + log.j[r] + 1
    order = stable_order(keys)
    numbers, values = np.empty((k, 3), np.int64), np.empty((k, 4))
    for r in range(k):
        q = order[r]
        numbers[r, 0], numbers[r, 1], numbers[r, 2] = log.kind[q], log.i[q], log.j[q]
        values[r, 0], values[r, 1], values[r, 2], values[r, 3] = log.time[q], log.impulse[q], log.point[q, 0], \
            log.point[q, 1]
    for r in range(k):
        log.kind[r], log.i[r], log.j[r] = numbers[r, 0], numbers[r, 1], numbers[r, 2]
        log.time[r], log.impulse[r], log.point[r, 0], log.point[r, 1] = values[r, 0], values[r, 1], values[r, 2], \
            values[r, 3]
    return True


def log_events(log: EventLog, time_offset: float = 0.0, ordered: bool = False) -> Events:
    """The logged collisions as Events in canonical (time, kind, i, j) order. ordered: they are
    in that order already (into_canonical_order, run where they were logged), or are to be
    sorted by the caller."""
    k = int(log.size[0])
    events = Events(log.time[:k] + time_offset, log.kind[:k].copy(), log.i[:k].copy(), log.j[:k].copy(),
                    log.impulse[:k].copy(), log.point[:k].copy())
    return events if ordered else Events.concatenate([events])
