"""collisim's kernels are cached in a folder named by all of its sources, so a change to any
source compiles them again; processes compiling into that folder at once take turns
(core/compiling.py)."""
import os
import subprocess
import sys
import time

# A package's kernels, cached where collisim keeps its own: in compiling.cache_folder(package).
RUN = """
import sys, numba
from collisim.core import compiling
numba.config.CACHE_DIR = compiling.cache_folder(sys.argv[1])
compiling.save_one_process_at_a_time()
sys.path.insert(0, sys.argv[1])
from outer import outer
print(outer())
"""


def run_cached(package, cache) -> str:
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    done = subprocess.run([sys.executable, "-c", RUN, str(package)], env=env, capture_output=True, text=True,
                          check=True)
    return done.stdout.strip()


def write_package(package, inner_value: float) -> None:
    package.mkdir(exist_ok=True)
    (package / "inner.py").write_text(f"from numba import njit\n\n@njit(cache=True)\ndef inner():\n"
                                      f"    return {inner_value}\n")
    # a long body: compiling it takes long enough for two processes to meet
    steps = "".join(f"    x = x * 0.5 + {k}.0 if x > {k} else x + 1.0\n" for k in range(200))
    (package / "outer.py").write_text("from numba import njit\nfrom inner import inner\n\n\n@njit(cache=True)\n"
                                      "def outer():\n    x = 0.0\n" + steps + "    return inner() + 0.5 + 0.0 * x\n")


def test_a_kernel_compiles_again_when_a_kernel_it_calls_changes_in_another_file(tmp_path):
    # numba's own stamp is the caller's file alone: outer() kept returning the cached 1.5
    package, cache = tmp_path / "package", tmp_path / "cache"
    write_package(package, 1.0)
    assert run_cached(package, cache) == "1.5"
    assert run_cached(package, cache) == "1.5"   # loaded from the cache
    write_package(package, 2.0)
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


# Two processes that compile one kernel for two argument types at the same moment: each waits for
# the file `go`, calls it, and reports its value and when its compile began and ended.
AT_ONCE = """
import os, sys, time, numba
from numba.core import event
from collisim.core import compiling
numba.config.CACHE_DIR = sys.argv[2]
compiling.save_one_process_at_a_time()
sys.path.insert(0, sys.argv[1])
from outer import outer
times = []
class Timer(event.Listener):
    def on_start(self, e): times.append(time.time())
    def on_end(self, e): times.append(time.time())
event.register("numba:compile", Timer())
open(sys.argv[3], "w").close()
while not os.path.exists(os.path.join(sys.argv[1], "go")):
    time.sleep(0.001)
value = outer(int(sys.argv[4]) if sys.argv[4].isdigit() else float(sys.argv[4]))
print(value, min(times), max(times))
"""


def test_processes_compile_side_by_side_and_each_saves_its_own_kernel(tmp_path):
    package, cache = tmp_path / "package", tmp_path / "cache"
    write_package(package, 1.0)
    (package / "outer.py").write_text((package / "outer.py").read_text().replace("def outer():", "def outer(y):")
                                      .replace("return inner() + 0.5", "return 2 * y + inner() + 0.5"))
    cache.mkdir()
    ready = [tmp_path / f"ready{k}" for k in range(2)]
    workers = [subprocess.Popen([sys.executable, "-c", AT_ONCE, str(package), str(cache), str(flag), argument],
                                stdout=subprocess.PIPE, text=True) for flag, argument in zip(ready, ["3", "2.25"])]
    deadline = time.monotonic() + 120
    while not all(flag.exists() for flag in ready) and time.monotonic() < deadline:
        time.sleep(0.01)
    (package / "go").touch()
    reports = [worker.communicate(timeout=120)[0].split() for worker in workers]
    assert [report[0] for report in reports] == ["7.5", "6.0"]
    (start_a, end_a), (start_b, end_b) = [(float(report[1]), float(report[2])) for report in reports]
    assert start_a < end_b and start_b < end_a   # compiled at the same time, not in turns
    # a third process loads both from the cache, each the code compiled for its own type
    loaded = subprocess.run([sys.executable, "-c", f"""
import sys, numba
numba.config.CACHE_DIR = {str(cache)!r}
sys.path.insert(0, {str(package)!r})
from outer import outer
print(outer(3), outer(2.25), sum(outer.stats.cache_misses.values()), sum(outer.stats.cache_hits.values()))
"""], capture_output=True, text=True, check=True).stdout.split()
    assert loaded == ["7.5", "6.0", "0", "2"]


def test_a_kernel_that_returns_an_array_is_refused_as_it_compiles():
    # compiled without numba's runtime, a kernel handing back an array gives its caller a reference
    # nobody counted: the array was freed while still in use, and the process aborted much later
    # (a ray query's grid walk, "malloc(): unaligned tcache chunk")
    import numpy as np
    import pytest
    from numba import njit

    import collisim  # noqa: F401  (the check is on once collisim is imported)
    from collisim.core.compiling import compiled, kernel

    def first_half(values):
        return values[: values.shape[0] // 2]

    values = np.arange(6.0)
    assert compiled(first_half)(values).sum() == 3.0   # counted: fine
    unsafe = kernel(first_half)
    with pytest.raises(Exception, match="kernel first_half returns an array"):   # (numba wraps it in its TypingError)
        njit(lambda values: unsafe(values).sum())(values)
