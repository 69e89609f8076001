"""Drawing in bands of rows, one thread each: the compiled rasterizer (splat.py) draws a large
frame's discs in one band per core, with the same bytes as on one thread, and on the calling
thread alone while a video render's engine and encoder hold the other cores (on_one_thread).
"""
from __future__ import annotations

import concurrent.futures
import contextlib
import contextvars
import os

import numpy as np

BAND_DISCS = 1_000    # from this many discs on, the rows are split between threads (_bands)
RING_DISCS = 15       # a ring costs about as many discs' work (a 1 px ring ~400 ns, a sub-pixel disc ~26)


def _bands(rect, work: int, threads=None) -> list:
    """rect split into horizontal bands, one per thread, when drawing is worth it: `work` discs,
    or rings counted RING_DISCS each.

    Each band's thread draws every disc clipped to the band's rows, in order, so a pixel is
    blended by exactly the same discs in the same order with the same numbers as by one thread:
    the bytes do not depend on the bands. A disc across a border is visited by both threads
    (one computes the rows the other skips), and every thread tests every disc against its band
    (about 2 ns a disc). Measured alternating one thread and two bands on this project's 2-core
    machine, shuffled discs at 720p, medians of 9 to 15: 1 000 discs (4-9 px) 1.13 -> 0.87 ms, 25 000
    8.1 -> 5.1 ms, 250 000 24.7 -> 16.9 ms. Smaller draws win too in isolation (100 discs 0.47 ->
    0.36 ms), but under a millisecond a frame is not worth handing to a thread while a render's
    encoder holds the other core."""
    threads = _threads() if threads is None else threads
    left, top, right, bottom = rect
    if work < BAND_DISCS or threads < 2 or bottom - top < 2 * threads:
        return [rect]
    rows = np.linspace(top, bottom, threads + 1).round().astype(int)
    return [(left, int(a), right, int(b)) for a, b in zip(rows[:-1], rows[1:])]


_ONE_THREAD = contextvars.ContextVar("collisim_draw_on_one_thread", default=False)


@contextlib.contextmanager
def on_one_thread():
    """Draw on the calling thread only, whatever the work: for a video render, whose engine
    (engine/ahead.py) and encoder (io/base.py) already keep the other cores busy. Rendering
    25 000 discs at 720p, 180 frames on this project's 2-core machine, three runs each: 2.62-2.77 s
    drawing in bands, 2.40-2.64 s on one thread (the encode-only floor 1.81-1.93 s); 250 000
    discs, 60 frames: 2.37-2.50 s and 2.28-2.43 s (the engine sets the pace)."""
    token = _ONE_THREAD.set(True)
    try:
        yield
    finally:
        _ONE_THREAD.reset(token)


def _threads() -> int:
    return 1 if _ONE_THREAD.get() else _cores()


def _cores() -> int:
    return min(len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1, 8)


_POOL = {}   # process id -> its thread pool, made when first needed


def _pool():
    """This process's thread pool (a process forked from one that had a pool has none of its
    threads: it makes its own)."""
    pid = os.getpid()
    if pid not in _POOL:
        _POOL.clear()
        _POOL[pid] = concurrent.futures.ThreadPoolExecutor(_cores(), thread_name_prefix="collisim-splat")
    return _POOL[pid]


def in_bands(kernel, canvas, rect, work: int, *args) -> None:
    """kernel(canvas, band, *args) for each band of rect, the bands on a pool of threads (the
    kernels release the GIL)."""
    bands = _bands(rect, work)
    if len(bands) == 1:
        kernel(canvas, rect, *args)
        return
    for future in [_pool().submit(kernel, canvas, band, *args) for band in bands]:
        future.result()
