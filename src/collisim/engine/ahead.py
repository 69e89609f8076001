"""Simulate one block ahead: the engine steps the next block of frames on a thread of its own
while the player draws the current one and the writer encodes.

A render is three kinds of work: simulating, drawing and encoding. Drawing and encoding already
overlap (the writer encodes on a thread of its own); without this, every block the engine
simulated stopped the drawing, and the encoder ran dry of frames while it waited. The engines'
compiled blocks release the GIL (discrete.run_frames and ccd's events._run are nogil), so the
thread computes while the player's Python runs.

The blocks are the very blocks `stream` yields, in order: the bytes do not depend on the thread.
At most one block is computed ahead of the one being played, so memory holds two blocks.
"""
from __future__ import annotations

import atexit
import queue
import threading
import time
import weakref
from typing import Iterator

_BLOCK, _ERROR, _END = range(3)
THREAD_NAME = "collisim-engine"
_workers = []   # (thread, its stop) of every worker started and not yet joined at exit


class Ahead:
    """An iterator over `blocks` (an iterator) that computes the next item on a worker thread
    while the caller uses the current one. An error raised while computing a block is raised
    by the next() that would have returned it. `waited`: seconds next() spent waiting for the
    worker. close() stops the worker after the block in progress; so does dropping the
    iterator, and running out of blocks."""

    def __init__(self, blocks: Iterator):
        slot = queue.Queue(maxsize=1)      # the block computed ahead, or the end, or an error
        taken = threading.Semaphore(0)     # released when the caller takes a block
        stop = threading.Event()
        self._slot, self._taken, self._done, self.waited = slot, taken, False, 0.0
        # the worker holds the queue and the flags, not this object, so that dropping it stops the worker
        self._stop = weakref.finalize(self, _stop, slot, taken, stop)
        worker = threading.Thread(target=_work, args=(blocks, slot, taken, stop), name=THREAD_NAME, daemon=True)
        worker.start()
        _workers[:] = [(thread, stopper) for thread, stopper in _workers if thread.is_alive()]
        _workers.append((worker, self._stop))

    def __iter__(self):
        return self

    def __next__(self):
        if self._done:
            raise StopIteration
        start = time.perf_counter()
        kind, value = self._slot.get()
        self.waited += time.perf_counter() - start
        if kind == _BLOCK:
            self._taken.release()
            return value
        self._done = True
        if kind == _ERROR:
            raise value
        raise StopIteration

    def close(self) -> None:
        """Stop the worker: it finishes the block it is computing, if any, and exits."""
        self._done = True
        self._stop()


def _work(blocks: Iterator, slot: queue.Queue, taken: threading.Semaphore, stop: threading.Event) -> None:
    """The worker: put each block in the slot, then wait until it is taken (or stop is set)."""
    try:
        for block in blocks:
            slot.put((_BLOCK, block))
            del block   # the caller holds it now; the next one is computed only once it is taken
            while not taken.acquire(timeout=0.1):
                if stop.is_set():
                    return
            if stop.is_set():
                return
    except BaseException as error:   # handed to the caller's next()
        slot.put((_ERROR, error))
    else:
        slot.put((_END, None))


def _stop(slot: queue.Queue, taken: threading.Semaphore, stop: threading.Event) -> None:
    stop.set()
    taken.release()
    try:
        slot.get_nowait()   # a block computed ahead and not wanted now
    except queue.Empty:
        pass


def computing() -> bool:
    """Whether a worker is still running: computing a block (the first one compiles the engine),
    or holding one not yet taken."""
    return any(thread.is_alive() for thread, _ in _workers)


@atexit.register
def _end_workers() -> None:
    """At the interpreter's exit, stop every worker and wait for the block it is in. Python's
    teardown frees numba's and LLVM's objects, and a worker still compiling under it made LLVM
    abort the process (a script ended by Ctrl-C in its first render). A stopped worker ends once
    its block is done; the CLI does not wait (cli.run)."""
    for thread, stopper in _workers:
        stopper()
        thread.join()
