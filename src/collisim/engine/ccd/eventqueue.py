"""The future-event queue: a min-heap (4-ary) of predicted events.

An event is (time, key, count_i, count_j). The key packs (kind, i, j) into one
integer so that events at the same time are always processed in the same order,
by kind, then i, then j: simultaneous events are deterministic.

Events are never searched for and removed when they become wrong (a particle
whose velocity changed invalidates all its predictions). Instead every particle
has a collision counter, each event remembers the counters of its particles when
it was predicted, and an event whose counters are out of date is simply skipped
when it reaches the top (the lazy deletion of Rapaport and Lubachevsky).

The one exception is each particle's own next event (a cell crossing, a wall, a segment, a
slide off its end): the queue knows where it is (slot_of), and a new one takes its place and
moves up or down from there (push_one_body). Those had been most of the events skipped: on
the dense gas, 1.07 an event processed, against 0.47 pair events.
"""
from collections import namedtuple

import numpy as np

from ...core.arrays import copy_rows
from ...core.compiling import compiled, constructor, inlined, kernel
from ...core.kinds import SEGMENT

assert SEGMENT < 3  # the bookkeeping kinds below sort after every collision kind

# Kinds of event, in the order simultaneous events are processed. The collision kinds
# (kinds.WALL, PAIR, SEGMENT) come first and are recorded; these only update the bookkeeping.
CELL = 3        # j = direction of the crossing: 0 -x, 1 +x, 2 -y, 3 +y
SLIDE_OFF = 4   # j = the segment a resting particle slides off the end of

EventQueue = namedtuple("EventQueue", ["time", "key", "count_i", "count_j", "size", "slot_of"])
EventQueue.__doc__ = """time (c,) float64; key, count_i, count_j (c,) int64: a heap of capacity c.
size (1,) int64: the number of events in it. count_j is < 0 for one-particle events: -1 for one
queued with push, ONE_BODY - i for body i's own event (push_one_body), which the queue keeps
track of: slot_of (n,) int64 holds the slot of each body's own event, or -1 for none."""

# count_j of body i's own event (its next crossing, wall, segment or slide): ONE_BODY - i
ONE_BODY = -2


@constructor(error_model="numpy")
def new_queue(capacity, bodies):
    """An empty queue with room for `capacity` events, keeping track of `bodies` bodies' own events."""
    return _empty_queue(capacity, np.full(bodies, -1, np.int64))


@constructor(error_model="numpy")
def _empty_queue(capacity, slot_of):
    """An empty queue with room for `capacity` events, keeping track in slot_of (n,)."""
    return EventQueue(np.empty(capacity), np.empty(capacity, np.int64), np.empty(capacity, np.int64),
                      np.empty(capacity, np.int64), np.zeros(1, np.int64), slot_of)


@kernel
def event_key(kind, i, j, base):
    """Pack (kind, i, j), each of i, j < base, into an integer ordered like the tuple."""
    return (kind * base + i) * base + j


@kernel
def key_parts(key, base):
    """(kind, i, j) from event_key."""
    return key // (base * base), (key // base) % base, key % base


@kernel
def is_current(queue, slot, counters, base):
    """Were the counters of the event's particles unchanged since it was predicted?"""
    kind, i, j = key_parts(queue.key[slot], base)
    count_i, count_j = queue.count_i[slot], queue.count_j[slot]
    return count_i == counters[i] and (count_j < 0 or count_j == counters[j])


@kernel
def _before(time_a, key_a, time_b, key_b):
    """Does event a come before event b? By time, ties by key."""
    return time_a < time_b or (time_a == time_b and key_a < key_b)


ARITY = 4   # children per node: a shallower heap, whose four children share a cache line or two


@kernel
def _move(queue, source, target):
    """Copy the event in slot source to slot target."""
    _place(queue, target, queue.time[source], queue.key[source], queue.count_i[source], queue.count_j[source])


@kernel
def _place(queue, slot, time, key, count_i, count_j):
    """Write an event into slot, noting where a body's own event now is."""
    queue.time[slot], queue.key[slot], queue.count_i[slot], queue.count_j[slot] = time, key, count_i, count_j
    if count_j <= ONE_BODY:
        queue.slot_of[ONE_BODY - count_j] = slot


@kernel
def _sift_up(queue, slot, time, key, count_i, count_j):
    """Put the event (time, key, count_i, count_j) into the hole at slot, moving it up: each
    parent it comes before moves down into the hole, and the event is written once."""
    while slot > 0:
        parent = (slot - 1) // ARITY
        if not _before(time, key, queue.time[parent], queue.key[parent]):
            break
        _move(queue, parent, slot)
        slot = parent
    _place(queue, slot, time, key, count_i, count_j)


@kernel
def _sift_down(queue, slot, time, key, count_i, count_j):
    """Put the event into the hole at slot, moving it down past every earliest child that comes
    before it."""
    size = queue.size[0]
    while True:
        first = ARITY * slot + 1
        if first >= size:
            break
        best = first
        for child in range(first + 1, min(first + ARITY, size)):
            if _before(queue.time[child], queue.key[child], queue.time[best], queue.key[best]):
                best = child
        if not _before(queue.time[best], queue.key[best], time, key):
            break
        _move(queue, best, slot)
        slot = best
    _place(queue, slot, time, key, count_i, count_j)


@kernel
def push(queue, time, key, count_i, count_j):
    """Add an event; the caller has reserved room for it."""
    slot = queue.size[0]
    queue.size[0] = slot + 1
    _sift_up(queue, slot, time, key, count_i, count_j)


@inlined
def push_one_body(queue, time, key, count, body):
    """Queue body's own next event (count: its counter), in place of the one it has in the queue,
    which its new counter has put out of date: moved up or down from that slot rather than left
    to be popped and skipped (1.07 such pops per event processed on the dense gas). The caller
    has reserved room for it."""
    slot = queue.slot_of[body]
    if slot < 0:
        push(queue, time, key, count, ONE_BODY - body)
    elif _before(time, key, queue.time[slot], queue.key[slot]):
        _sift_up(queue, slot, time, key, count, ONE_BODY - body)
    else:
        _sift_down(queue, slot, time, key, count, ONE_BODY - body)


@inlined
def pop(queue):
    """Remove the earliest event and return it as (time, key, count_i, count_j).

    The hole the earliest event leaves at the top goes down to a leaf along the earliest
    children, and the last event goes up into it from there (Wegener's bottom-up deletion):
    the last event belongs near the leaves, so this compares about a quarter less than
    sifting it down from the top, and choosing the earliest of four children is written
    without branches."""
    top = (queue.time[0], queue.key[0], queue.count_i[0], queue.count_j[0])
    if top[3] <= ONE_BODY:
        queue.slot_of[ONE_BODY - top[3]] = -1
    last = queue.size[0] - 1
    queue.size[0] = last
    if last > 0:
        slot = _hole_to_leaf(queue, last)
        _sift_up(queue, slot, queue.time[last], queue.key[last], queue.count_i[last], queue.count_j[last])
    return top


@inlined
def _hole_to_leaf(queue, size):
    """Move the hole at the top down to a leaf of the heap's first `size` slots, each step
    filling it with the earliest child; returns the leaf."""
    times, keys = queue.time, queue.key
    slot = 0
    while True:
        first = ARITY * slot + 1
        if first + ARITY <= size:   # four children: the earliest, by selects
            best, best_time, best_key = first, times[first], keys[first]
            for child in range(first + 1, first + ARITY):
                time, key = times[child], keys[child]
                earlier = (time < best_time) | ((time == best_time) & (key < best_key))
                best = child if earlier else best
                best_time = time if earlier else best_time
                best_key = key if earlier else best_key
        elif first < size:
            best = first
            for child in range(first + 1, size):
                if _before(times[child], keys[child], times[best], keys[best]):
                    best = child
        else:
            return slot
        _move(queue, best, slot)
        slot = best


@kernel
def clear(queue):
    """Empty the queue."""
    queue.size[0] = 0
    for body in range(queue.slot_of.shape[0]):
        queue.slot_of[body] = -1


@kernel
def has_room(queue, extra):
    """Has the queue room for `extra` more events?"""
    return queue.size[0] + extra <= queue.time.shape[0]


@compiled(error_model="numpy")
def reserve(queue, extra, counters, base):
    """A queue with room for `extra` more events: the same one, or one with the
    out-of-date events dropped, or a larger copy."""
    capacity = queue.time.shape[0]
    if queue.size[0] + extra <= capacity:
        return queue
    kept = 0
    for slot in range(queue.size[0]):
        if is_current(queue, slot, counters, base):
            queue.time[kept], queue.key[kept] = queue.time[slot], queue.key[slot]
            queue.count_i[kept], queue.count_j[kept] = queue.count_i[slot], queue.count_j[slot]
            kept += 1
    while 2 * (kept + extra) > capacity:
        capacity *= 2
    larger = _empty_queue(capacity, queue.slot_of)
    clear(larger)   # (the bodies' own events: found again below)
    copy_rows(queue.time, larger.time, kept)   # (arrays.py: not a slice assignment)
    copy_rows(queue.key, larger.key, kept)
    copy_rows(queue.count_i, larger.count_i, kept)
    copy_rows(queue.count_j, larger.count_j, kept)
    larger.size[0] = kept
    for slot in range(kept):
        body = ONE_BODY - larger.count_j[slot]
        if body >= 0:
            larger.slot_of[body] = slot
    for slot in range((kept - 2) // ARITY, -1, -1):   # every node with a child, deepest first
        _sift_down(larger, slot, larger.time[slot], larger.key[slot], larger.count_i[slot], larger.count_j[slot])
    return larger
