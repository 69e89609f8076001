"""Functions compiled without numba's reference counting (compiling.uncounted): none may return
an array, the event loop's per-event functions are among them, and the loop's stopping to let
its queue and log grow changes no byte."""
from collections import namedtuple

import numpy as np
import pytest
from numba import njit
from numba.core.errors import TypingError

from collisim import compiling
from collisim.core.compiling import uncounted
from collisim.engine.ccd import eventqueue, events, frame_events, predict

# The functions an event runs; each must stay uncounted (the event loop's speed rests on it).
PER_EVENT = ((frame_events, "frame_events"), (frame_events, "collect_collisions"), (frame_events, "reschedule"),
             (frame_events, "record_contacts"), (frame_events, "apply_bookkeeping"), (events, "sample"))


# The functions an event runs that are handed the state (namedtuples of arrays): each must stay
# inlined into the loop (compiling.inlined; as calls, their arguments cost a third of an event).
INLINED = ((frame_events, "collect_collisions"), (frame_events, "reschedule"), (predict, "predict_solo"),
           (predict, "predict_pairs"), (predict, "next_cell_crossing"), (predict, "next_wall_hit"),
           (eventqueue, "pop"))

Pair = namedtuple("Pair", ["a", "b"])


def _sum_at(pair, k):
    return pair.a[k] + pair.b[k]


@uncounted
def _handed_back(values):
    return values


@uncounted
def _in_a_tuple(values, k):
    return k, (values, values[k])


@njit(cache=True)
def _a_view(values):     # counted alone; called from an uncounted function, compiled uncounted too
    return values[1:]


@uncounted
def _takes_a_view(values):
    return _a_view(values)[0]


@uncounted
def _an_element(values, k):
    return values[k], (k, values[k] * 2.0)


def test_an_uncounted_function_that_returns_an_array_does_not_compile():
    """The caller would own a reference nobody counted, and free the array while it is in use.
    A function an uncounted one calls is compiled uncounted too, and may not make an array."""
    values = np.arange(4.0)
    for call in (lambda: _handed_back(values), lambda: _in_a_tuple(values, 1)):
        with pytest.raises(TypingError, match="may not return an array"):
            call()
    with pytest.raises(TypingError, match="returning of array"):   # numba's refusal of a new array
        _takes_a_view(values)
    assert _an_element(values, 2) == (2.0, (2, 4.0))


def test_the_per_event_functions_are_uncounted():
    for module, name in PER_EVENT:
        assert getattr(module, name).targetoptions.get("_nrt") is False, name


def test_the_per_event_functions_handed_the_state_are_inlined():
    for module, name in INLINED:
        dispatcher = getattr(module, name)
        assert dispatcher._compiler.pipeline_class is compiling._InlinedCompiler, name
        assert dispatcher.targetoptions.get("_nrt") is False, name


def test_the_inlined_pipeline_marks_a_function_for_llvm_to_inline_and_computes_the_same():
    """Compiled afresh (not cached, so its code can be read): the inlined pipeline asks LLVM to
    inline the function into every caller; numba's own does not."""
    inlined = njit(_nrt=False, error_model="numpy", pipeline_class=compiling._InlinedCompiler)(_sum_at)
    plain = njit(_nrt=False, error_model="numpy")(_sum_at)
    pair = Pair(np.arange(3.0), np.array([0.5, 0.25, 0.125]))
    assert inlined(pair, 2) == plain(pair, 2) == 2.125
    assert "alwaysinline" in next(iter(inlined.inspect_llvm().values()))
    assert "alwaysinline" not in next(iter(plain.inspect_llvm().values()))


def test_a_frame_is_the_same_whatever_room_the_queue_and_the_log_had():
    """The event loop stops mid-event to let the queue or the log grow (frame_events): starting
    from a queue with no room to spare and a tiny log, it grows both many times, and every
    sample and collision is the same as with room to spare."""
    from collisim.engine.ccd.eventqueue import new_queue
    from collisim.engine.ccd.events import run, sorted_log, start_event_loop

    rng = np.random.default_rng(5)
    n, frames = 60, 40
    positions = np.column_stack([np.tile(np.arange(1.0, 11.0), 6), np.repeat(np.arange(1.0, 13.0, 2.0), 10)])
    velocities = rng.normal(0.0, 3.0, (n, 2))

    def frames_of(tight):
        loop = start_event_loop(positions, velocities, (0.0, -9.81), 0.45, 1.0, (0, 0, 12, 14), 0.7, None, 2.0)
        if tight:   # the same heap, in a queue with room for nothing more
            q = loop.queue
            size = int(q.size[0])
            small = new_queue(size, n)
            for a, b in zip(small[:4], q[:4]):
                a[:] = b[:size]
            small.size[0] = size
            small.slot_of[:] = q.slot_of   # where each body's own event is: the same slots
            loop = loop._replace(queue=small)
        out_p, out_v = np.empty((frames, n, 2)), np.empty((frames, n, 2))
        counts, over = np.zeros((frames, 3), np.int64), np.zeros(frames, np.bool_)
        log, queue = run(loop, 1 / 30, 1, frames, 100_000, out_p, out_v, counts, over)
        return out_p, out_v, counts, sorted_log(log), queue.time.shape[0]

    roomy, tight = frames_of(False), frames_of(True)
    assert tight[4] > roomy[4] // 64      # the tight queue grew
    for a, b in zip(roomy[:3], tight[:3]):
        assert np.array_equal(a, b)
    for a, b in zip(roomy[3], tight[3]):
        assert np.array_equal(a, b)
    assert len(roomy[3][0]) > 1024        # more collisions than a new log has room for
