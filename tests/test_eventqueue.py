"""The event queue (engine/ccd/eventqueue.py) against Python's heapq: events come out by time,
ties by key, through any interleaving of pushes and pops, and growing it keeps exactly the
current events."""
import heapq

import numpy as np
import pytest

from collisim.engine.ccd.eventqueue import event_key, new_queue, pop, push, reserve
from collisim.model.kinds import PAIR


def _drain(queue):
    return [tuple(pop(queue))[:2] for _ in range(int(queue.size[0]))]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_pushes_and_pops_in_any_order_come_out_by_time_then_key(seed):
    rng = np.random.default_rng(seed)
    queue, reference = new_queue(4096), []
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
    queue, kept = new_queue(max(size, 1)), []
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
