"""collisim's kernels compile once per argument types, not once per constant passed (compiling.py)."""
import numpy as np
from numba import njit

import collisim  # noqa: F401  (installs the typing policy)

PROBE = '''
PAIR, WALL = 1, 0

def callee(out, kind, value):
    out[kind] += value

def caller(out):
    callee(out, PAIR, 2.0)
    callee(out, WALL, 3.0)
    callee(out, 1, -1.0)

def pick(pair, k):
    return pair[k]          # a heterogeneous tuple: only a constant k can index it

def picker():
    return pick((1, 2.5), 1) + pick((1, 2.5), 0)
'''


def compiled(module: str) -> dict:
    """The probe's functions compiled as if defined in `module`."""
    space = {"__name__": module}
    exec(PROBE, space)
    for name in ("callee", "pick"):
        space[name] = njit(space[name])
    for name in ("caller", "picker"):
        space[name] = njit(space[name])
    return space


def test_constants_do_not_multiply_compiles():
    probe = compiled("collisim._probe")
    out = np.zeros(2)
    probe["caller"](out)
    assert out.tolist() == [3.0, 1.0]
    assert len(probe["callee"].signatures) == 1   # (array, int64, float64), not one per constant


def test_a_callee_that_needs_a_constant_still_gets_it():
    probe = compiled("collisim._probe")
    assert probe["picker"]() == 3.5


def test_other_code_keeps_numbas_policy():
    probe = compiled("elsewhere")
    probe["caller"](np.zeros(2))
    assert len(probe["callee"].signatures) == 2   # Literal[int](1) (PAIR and 1) and Literal[int](0)


def test_first_run_counts_compiles_per_function():
    """The first-run benchmark's recorder: one count per signature compiled, a callee's time
    its own (not also its caller's)."""
    from numba.core import event
    from collisim.analysis.bench.first_run import CompileRecorder
    probe = compiled("collisim._probe")
    recorder = CompileRecorder()
    event.register("numba:compile", recorder)
    try:
        probe["caller"](np.zeros(2))
        probe["callee"](np.zeros(2, np.int64), 0, 1)   # a second signature, from Python
    finally:
        event.unregister("numba:compile", recorder)
    callee, caller = recorder.functions["collisim._probe.callee"], recorder.functions["collisim._probe.caller"]
    assert (callee["compiles"], caller["compiles"]) == (2, 1)
    assert callee["seconds"] > 0 and caller["seconds"] > 0
    assert callee["signatures"][1] == "array(int64, 1d, C), int64, int64"
