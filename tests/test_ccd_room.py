"""ccd's event loop stops mid-event to let its queue or its log grow: no byte depends on the room."""
import numpy as np


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
