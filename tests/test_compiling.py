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
