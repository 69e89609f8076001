"""Ending a run by a signal (Ctrl-C, SIGTERM, SIGHUP) cleanly, even in the middle of compiled code.

A signal's Python handler runs at the next point where the interpreter checks for one. After a
compiled (numba) call that point is usually inside the call's return: numba builds the returned
Python objects partly by calling back into Python (numba.core.serialize._numba_unpickle for
types and constants, a named tuple's constructor), and an exception raised there is lost by the
boxing code: the process dies of a segmentation fault, or Python reports a SystemError, instead
of cleaning up. So the handler here never raises while such a call is on the stack: it traces
the interpreter (sys.settrace) until the next line or return of ordinary code, and raises there.

That code may itself have been called from C: the interrupt raised in a Python hook that numpy's
C code called came out of it as a TypeError of numpy's. So once a signal has landed, whatever
error ends the block is taken for the interrupt (signals_interrupt).
"""
from __future__ import annotations

import signal
import sys
import threading
from contextlib import contextmanager

STOP_SIGNALS = tuple(getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name))


# the modules of the Python code compiled code calls while it returns its result
BOXING_MODULES = ("numba.core.serialize", "namedtuple_")


class Interrupted(KeyboardInterrupt):
    """A signal that ends the command like Ctrl-C: every output's temporary is removed on the way
    out (a KeyboardInterrupt, so nothing that catches Exception swallows it)."""

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


def in_compiled_return(frame) -> bool:
    """Whether `frame`, or a frame that called it, is Python code that compiled code calls while
    returning its result."""
    while frame is not None:
        if str(frame.f_globals.get("__name__", "")).startswith(BOXING_MODULES):
            return True
        frame = frame.f_back
    return False


def _raise_in_ordinary_code(frame, raise_now):
    """Call raise_now() at the next line or return of code outside the compiled return that
    `frame` is in: in the frame that made the compiled call, or in any new frame. Returns the
    trace function it installed."""
    def local(frame, event, arg):
        if in_compiled_return(frame):
            return None
        sys.settrace(None)
        raise_now()

    def new_frame(frame, event, arg):
        return None if in_compiled_return(frame) else local

    caller = frame
    while caller is not None and in_compiled_return(caller):
        caller = caller.f_back
    if caller is not None:
        caller.f_trace, caller.f_trace_lines = local, True
    sys.settrace(new_frame)
    return new_frame


@contextmanager
def signals_interrupt(signals=STOP_SIGNALS):
    """While open, each of `signals` raises Interrupted in the main thread (never while compiled
    code returns its result: see the module); once one has, further ones are ignored so that
    the clean-up runs to its end, and any other error that leaves the block is the interrupt's
    (C code it ran through may raise its own in its place). Yields the signals received (a list:
    empty until one is). Outside the main thread it does nothing (Python delivers signals to
    the main thread only)."""
    if threading.current_thread() is not threading.main_thread():
        yield []
        return
    fired, tracing, closing = [], [], []

    def raise_now():
        raise Interrupted(fired[0])

    def stop(signum, frame):
        if fired or closing:
            return
        fired.append(signum)
        if in_compiled_return(frame) and sys.gettrace() is None:
            tracing.append(_raise_in_ordinary_code(frame, raise_now))
            return
        raise_now()

    # a signal may land while the handlers are being installed or put back: each handler is noted
    # before stop replaces it and put back whatever happens (a signal during the installing raises
    # inside the try), and once closing, a signal is ignored, so that none can cut the putting
    # back short (under load, one landing there left stop installed after the call had ended)
    previous = {}
    try:
        for number in signals:
            previous[number] = signal.getsignal(number)
            signal.signal(number, stop)
        yield fired
    except Exception as error:
        if fired:
            # the interrupt was raised in Python code that C code called, and the C code put an
            # error of its own in its place: numpy's tofile (the typeset text's cache,
            # render/textcache.py) asks isinstance(file, os.PathLike), whose hook is Python; the
            # interrupt raised there made numpy take the file for a path and raise TypeError
            raise Interrupted(fired[0]) from error
        raise
    finally:
        closing.append(True)
        if tracing and sys.gettrace() is tracing[0]:
            sys.settrace(None)
        for number, handler in previous.items():
            if handler is not None:   # None: installed from C, which Python cannot put back
                signal.signal(number, handler)


@contextmanager
def ctrl_c_safe():
    """For API calls that run compiled code (simulate, render): Ctrl-C still raises
    KeyboardInterrupt, but never where it would crash the process. Changes nothing when the
    caller has its own SIGINT handler, or off the main thread."""
    if (threading.current_thread() is not threading.main_thread()
            or signal.getsignal(signal.SIGINT) is not signal.default_int_handler):
        yield
        return
    with signals_interrupt((signal.SIGINT,)):
        yield
