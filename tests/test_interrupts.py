"""A signal (Ctrl-C; SIGTERM and SIGHUP in the command) that lands while compiled code runs ends
the run cleanly, never with a crash.

numba builds a call's returned Python objects partly by calling back into Python, and a
KeyboardInterrupt raised there by a signal handler is lost: the process dies of SIGSEGV, or
Python reports a SystemError (seen as a flaky render test under load). collisim.interrupts
raises the interrupt only once ordinary code runs again.
"""
import signal
import subprocess
import sys
import textwrap

import pytest

from conftest import as_a_fresh_process

COMPILED_CALLS = textwrap.dedent("""
    import os, signal, threading
    from collections import namedtuple
    import numpy as np
    from numba import njit
    from collisim.interrupts import Interrupted, signals_interrupt
    Pair = namedtuple("Pair", ["a", "b"])

    @njit
    def work(n):
        s = 0.0
        for i in range(n):
            s += np.sqrt(i)
        x = np.zeros(1, np.int8)
        x[0] = s
        return Pair(x, x), x   # returned through numba's boxing, which calls into Python

    work(10)
    with signals_interrupt():
        threading.Timer(0.3, os.kill, (os.getpid(), signal.{name})).start()
        try:
            for _ in range(100_000):   # each call ~ms of compiled code: the signal lands there
                work(2_000_000)
        except Interrupted as interrupt:
            print("interrupted", signal.Signals(interrupt.signum).name)
""")


def run(script: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=300,
                          preexec_fn=as_a_fresh_process)


@pytest.mark.parametrize("name", ["SIGTERM", "SIGHUP", "SIGINT"])
def test_a_stop_signal_during_compiled_calls_interrupts_cleanly(name):
    result = run(COMPILED_CALLS.replace("{name}", name))
    assert result.returncode == 0, result.stderr[-2000:]
    assert result.stdout.strip() == f"interrupted {name}"


@pytest.mark.parametrize("method", ["discrete", "ccd"])
def test_ctrl_c_during_simulate_raises_keyboard_interrupt_and_the_process_lives_on(method):
    result = run(textwrap.dedent(f"""
        import os, signal, sys, threading
        import numpy as np
        import collisim
        scene = collisim.load_scene("particles_250").replace(method="{method}")
        collisim.simulate(scene.replace(seconds=0.1))          # compiled and cached first
        stopped = 0
        for delay in np.random.default_rng(1).uniform(0.05, 0.4, 6):
            threading.Timer(delay, os.kill, (os.getpid(), signal.SIGINT)).start()
            try:
                collisim.simulate(scene.replace(seconds=600.0))
            except KeyboardInterrupt:
                stopped += 1
        assert sys.gettrace() is None and signal.getsignal(signal.SIGINT) is signal.default_int_handler
        print(stopped, collisim.simulate(scene.replace(seconds=0.1)).frames)   # still usable
    """))
    assert result.returncode == 0, result.stderr[-2000:]
    assert result.stdout.split() == ["6", "6"]


def test_under_a_callers_own_handler_or_off_the_main_thread_nothing_changes():
    result = run(textwrap.dedent("""
        import signal, threading
        from collisim.interrupts import ctrl_c_safe
        mine = lambda signum, frame: None
        signal.signal(signal.SIGINT, mine)
        with ctrl_c_safe():
            assert signal.getsignal(signal.SIGINT) is mine
        signal.signal(signal.SIGINT, signal.default_int_handler)
        seen = []
        def in_thread():
            with ctrl_c_safe():
                seen.append(signal.getsignal(signal.SIGINT) is signal.default_int_handler)
        thread = threading.Thread(target=in_thread)
        thread.start(); thread.join()
        with ctrl_c_safe():
            seen.append(signal.getsignal(signal.SIGINT) is not signal.default_int_handler)
        seen.append(signal.getsignal(signal.SIGINT) is signal.default_int_handler)
        print(seen)
    """))
    assert result.returncode == 0, result.stderr
    assert result.stdout.strip() == "[True, True, True]"


def test_a_signal_while_the_handlers_are_installed_or_put_back_leaves_none_behind():
    """A signal that lands between installing the handler and entering the block (or while the
    handlers are put back) must not leave collisim's handler installed: under load, Ctrl-C
    during simulate's first instants did."""
    result = run(textwrap.dedent("""
        import os, signal
        from collisim import interrupts
        real = signal.signal

        def install_then_signal(number, handler):
            before = real(number, handler)
            if handler is not signal.default_int_handler:
                os.kill(os.getpid(), signal.SIGINT)   # lands at the next bytecode: still installing
            return before

        interrupts.signal.signal = install_then_signal
        try:
            with interrupts.signals_interrupt((signal.SIGINT,)):
                print("entered")
        except KeyboardInterrupt as stop:
            print("interrupted", type(stop).__name__)
        interrupts.signal.signal = real
        print(signal.getsignal(signal.SIGINT) is signal.default_int_handler)
    """))
    assert result.returncode == 0, result.stderr[-2000:]
    assert result.stdout.split() == ["interrupted", "Interrupted", "True"]


REPLACED = textwrap.dedent("""
    import os, signal, time
    from collisim.interrupts import Interrupted, signals_interrupt
    try:
        with signals_interrupt():
            try:
                os.kill(os.getpid(), signal.SIGTERM)
                time.sleep(5)   # the handler raises here
            except Interrupted:
                # what C code that the interrupt ran through may do with it (numpy's tofile)
                raise TypeError("expected str, bytes or os.PathLike object, not BufferedWriter")
    except Interrupted as interrupt:
        print("interrupted", signal.Signals(interrupt.signum).name, type(interrupt.__cause__).__name__)
""")


def test_an_error_that_c_code_puts_in_place_of_the_interrupt_still_interrupts():
    # seen under load in tests/test_formats.py's render signalled mid-render: a traceback and
    # status 1 instead of "interrupted (SIGTERM); no file written", the signal having landed
    # while the typeset text's cache was written (np.save)
    result = run(REPLACED)
    assert result.returncode == 0, result.stderr[-2000:]
    assert result.stdout.strip() == "interrupted SIGTERM TypeError"
