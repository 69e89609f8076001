"""collisim's kernels compile once per argument types, not once per constant passed; their cache
entries go stale when any of the package's sources changes (compiling.py)."""
import os
import subprocess
import sys
import textwrap

import numpy as np
from numba import njit

from collisim.core.compiling import plain_constants

plain_constants()   # the typing policy, as importing collisim installs it

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


CALLER = """
import sys
import collisim.core.compiling as compiling
compiling.PACKAGE = sys.argv[1]          # stamp this folder's kernels as if they were collisim's
sys.path.insert(0, sys.argv[1])
from outer import outer
print(outer())
"""


def run_cached(package, cache) -> str:
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    done = subprocess.run([sys.executable, "-c", CALLER, str(package)], env=env, capture_output=True, text=True,
                          check=True)
    return done.stdout.strip()


def test_a_kernel_compiles_again_when_a_kernel_it_calls_changes_in_another_file(tmp_path):
    # numba's own stamp is the caller's file alone: outer() kept returning the cached 1.0
    package, cache = tmp_path / "package", tmp_path / "cache"
    package.mkdir()
    (package / "inner.py").write_text("from numba import njit\n\n@njit(cache=True)\ndef inner():\n    return 1.0\n")
    (package / "outer.py").write_text(textwrap.dedent("""
        from numba import njit
        from inner import inner

        @njit(cache=True)
        def outer():
            return inner() + 0.5
        """))
    assert run_cached(package, cache) == "1.5"
    assert run_cached(package, cache) == "1.5"   # loaded from the cache
    (package / "inner.py").write_text("from numba import njit\n\n@njit(cache=True)\ndef inner():\n    return 2.0\n")
    assert run_cached(package, cache) == "2.5"


def test_the_package_digest_sees_every_source_and_nothing_else(tmp_path):
    from collisim.core.compiling import package_digest

    (tmp_path / "sub").mkdir()
    (tmp_path / "a.py").write_text("x = 1\n")
    (tmp_path / "sub" / "b.py").write_text("y = 2\n")
    first = package_digest(str(tmp_path))
    package_digest.cache_clear()
    (tmp_path / "notes.txt").write_text("not a source")
    (tmp_path / "__pycache__").mkdir()
    (tmp_path / "__pycache__" / "c.py").write_text("z = 3\n")
    assert package_digest(str(tmp_path)) == first
    package_digest.cache_clear()
    (tmp_path / "sub" / "b.py").write_text("y = 3\n")
    assert package_digest(str(tmp_path)) != first
    package_digest.cache_clear()


def test_two_processes_saving_one_kernel_for_two_types_at_once_never_mix_their_entries(tmp_path):
    """The interleaving numba's numbered data files lose: A takes number 1 and writes its index;
    B, which read the index before that, takes number 1 too and writes index and code; then A
    writes its code over B's, under B's index entry. Replayed here in one process: B's whole
    save runs inside A's, where A writes its code, and B reads the index A had not yet written.
    Every entry the index ends with must load its own kernel's code."""
    from numba import types
    from numba.core.caching import IndexDataCacheFile

    from collisim.core.compiling import PACKAGE, package_digest

    stamp = ((1.0, 100), package_digest(PACKAGE))   # a collisim kernel's stamp (stamp_with_package)
    machine = ("x86_64-unknown-linux-gnu", "cpu", "")
    key_a, key_b = ((types.float64,), machine, ("code", "")), ((types.int64,), machine, ("code", ""))
    a, b = (IndexDataCacheFile(str(tmp_path), "module.kernel-10.py311", stamp) for _ in range(2))
    b._load_index = lambda: {}   # B read the index before A wrote it
    write_a = a._save_data

    def a_writes_after_b(name, data):
        b.save(key_b, "code for int64")
        write_a(name, data)

    a._save_data = a_writes_after_b
    a.save(key_a, "code for float64")
    reader = IndexDataCacheFile(str(tmp_path), "module.kernel-10.py311", stamp)
    index = reader._load_index()
    assert index, "the index lost both entries"
    expected = {key_a: "code for float64", key_b: "code for int64"}
    for key in index:
        assert reader.load(key) == expected[key]


def test_cache_entry_names_are_the_same_in_every_process():
    """A kernel's entry is named by its key as text: the same argument types give the same file
    in any process, however many types it made before (a named tuple's type is numbered by
    each process in the order it meets it)."""
    probe = textwrap.dedent("""
        import sys, numpy as np
        from numba import typeof, types
        from collisim.core.compiling import _described
        from collisim.engine.discrete import Bodies
        if sys.argv[1] == "other first":
            typeof((np.zeros(3), 1.0, np.zeros((2, 2), np.int64)))
        print(_described(((typeof(Bodies(*[np.zeros(3)] * 11)), types.float64), ("machine",), ("code", ""))))
        """)
    names = {subprocess.run([sys.executable, "-c", probe, order], capture_output=True, text=True,
                            check=True).stdout for order in ("plain", "other first")}
    assert len(names) == 1
    assert "collisim.engine.discrete.Bodies" in names.pop()
