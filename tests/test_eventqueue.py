"""The event queue (engine/ccd/eventqueue.py) against Python's heapq: events come out by time,
ties by key, through any interleaving of pushes and pops, and growing it keeps exactly the
current events."""
import heapq

import numpy as np
import pytest

from collisim.engine.ccd.eventqueue import (ARITY, CELL, ONE_BODY, event_key, new_queue, pop, push, push_one_body,
                                          reserve)
from collisim.core.kinds import PAIR


def _drain(queue):
    return [tuple(pop(queue))[:2] for _ in range(int(queue.size[0]))]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_pushes_and_pops_in_any_order_come_out_by_time_then_key(seed):
    rng = np.random.default_rng(seed)
    queue, reference = new_queue(4096, 0), []
    for _ in range(1500):
        if reference and rng.random() < 0.4:
            assert tuple(pop(queue))[:2] == heapq.heappop(reference)
        else:   # few distinct times: many ties, decided by the key
            time, key = float(rng.integers(0, 40)) / 8, int(rng.integers(0, 10_000))
            push(queue, time, key, 0, -1)
            heapq.heappush(reference, (time, key))
        assert queue.size[0] == len(reference)
    assert _drain(queue) == sorted(reference)
    assert queue.size[0] == 0


@pytest.mark.parametrize("size", [0, 1, 2, 5, 17, 300])
def test_growing_keeps_the_current_events_and_their_order(size):
    """reserve drops events whose counters are out of date and rebuilds the heap from the rest."""
    rng = np.random.default_rng(size)
    base, n = 1000, 50
    counters = np.zeros(n, np.int64)
    queue, kept = new_queue(max(size, 1), 0), []
    for _ in range(size):
        i, j = (int(v) for v in rng.choice(n, 2, replace=False))
        time, key = float(rng.integers(0, 30)), event_key(PAIR, i, j, base)
        stale = rng.random() < 0.5
        push(queue, time, key, counters[i] - stale, counters[j])
        if not stale:
            kept.append((time, key))
    grown = reserve(queue, 10, counters, base)
    assert grown.time.shape[0] >= len(kept) + 10
    assert _drain(grown) == sorted(kept)


def _tracking_is_exact(queue):
    """Each body's own event is where slot_of says, and nowhere else; the heap is in order."""
    size = int(queue.size[0])
    owner = ONE_BODY - queue.count_j[:size]
    for body in range(queue.slot_of.shape[0]):
        slots = np.flatnonzero(owner == body)
        assert list(slots) == ([queue.slot_of[body]] if queue.slot_of[body] >= 0 else []), body
    for child in range(1, size):
        parent = (child - 1) // ARITY
        assert (queue.time[parent], queue.key[parent]) <= (queue.time[child], queue.key[child])


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_bodys_own_event_replaces_the_one_it_had(seed):
    """push_one_body moves a body's event in place (up or down), pop forgets it, growing keeps
    track of it: the events come out as from a heapq holding each body's latest event only,
    mixed with pair events, ties decided by the key."""
    rng = np.random.default_rng(seed)
    bodies, base = 40, 1000
    counters = np.zeros(bodies, np.int64)
    queue, own, pairs = new_queue(8, bodies), {}, []
    for step in range(3000):
        roll = rng.random()
        if queue.size[0] and roll < 0.35:
            time, key, count_i, count_j = pop(queue)
            expected = min(list(own.values()) + pairs)
            assert (time, key) == expected
            if count_j <= ONE_BODY:
                del own[ONE_BODY - count_j]
            else:
                pairs.remove(expected)
        else:
            queue = reserve(queue, 1, counters, base)   # grows it now and then: tracking survives
            time = float(rng.integers(0, 40)) / 8       # few distinct times: many ties
            if roll < 0.8:
                body = int(rng.integers(bodies))
                key = event_key(CELL, body, int(rng.integers(4)), base)
                push_one_body(queue, time, key, counters[body], body)
                own[body] = (time, key)
            else:
                i, j = sorted(int(v) for v in rng.choice(bodies, 2, replace=False))
                key = event_key(PAIR, i, j, base)
                push(queue, time, key, counters[i], counters[j])
                pairs.append((time, key))
        assert queue.size[0] == len(own) + len(pairs)
        if step % 100 == 0:
            _tracking_is_exact(queue)
    _tracking_is_exact(queue)
    assert _drain(queue) == sorted(list(own.values()) + pairs)
    assert np.all(queue.slot_of == -1)


def test_growing_forgets_the_own_events_that_went_out_of_date():
    bodies, base = 6, 100
    counters = np.zeros(bodies, np.int64)
    queue = new_queue(6, bodies)
    for body in range(bodies):
        push_one_body(queue, float(bodies - body), event_key(CELL, body, 0, base), 0, body)
    counters[[1, 4]] += 1   # their events are out of date
    grown = reserve(queue, 10, counters, base)
    assert list(grown.slot_of[[1, 4]]) == [-1, -1] and np.all(grown.slot_of[[0, 2, 3, 5]] >= 0)
    _tracking_is_exact(grown)
    assert [key for _, key in _drain(grown)] == [event_key(CELL, body, 0, base) for body in (5, 3, 2, 0)]
