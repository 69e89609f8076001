"""What numba's compile costs per kernel and per level of calls, on kernels of the same body.

    python benchmarks/compile_depth.py            # 30 kernels: flat, chain, chain inlined

flat: the kernels all called from one kernel (two levels); chain: each calls the next (30
levels); inlined: the chain with numba's inline="always". numba makes a kernel's machine code
again for every kernel above it (a kernel carries the code of all it calls), so the chain costs
more than the flat calls, though it compiles the same code. Each case runs in a fresh process,
without the cache; wall seconds of the first call.
"""
import subprocess
import sys

BODY = """    s = 0.0
    for i in range(a.shape[0]):
        if a[i] > x:
            s += a[i] * x - b[i] / (1.0 + x)
        else:
            s -= b[i] * a[i] + x
"""


def source(mode: str, count: int) -> str:
    decorator = "@njit(inline='always')" if mode == "inlined" else "@njit"
    lines = ["import time", "import numpy as np", "from numba import njit"]
    for k in range(count):
        call = f"    s += f{k + 1}(a, b, x + 1.0)\n" if mode != "flat" and k + 1 < count else ""
        lines.append(f"{decorator}\ndef f{k}(a, b, x):\n{BODY}{call}    return s")
    calls = "    return f0(a, b, 0.0)\n" if mode != "flat" else \
        "    t = 0.0\n" + "".join(f"    t += f{k}(a, b, {k}.0)\n" for k in range(count)) + "    return t\n"
    lines.append(f"@njit\ndef top(a, b):\n{calls}")
    lines.append("start = time.perf_counter()\ntop(np.ones(4), np.ones(4))\nprint(round(time.perf_counter() - start, 2))")
    return "\n".join(lines)


if __name__ == "__main__":
    count = int(sys.argv[1]) if len(sys.argv) > 1 else 30
    for mode in ("flat", "chain", "inlined"):
        seconds = subprocess.run([sys.executable, "-c", source(mode, count)], capture_output=True, text=True,
                                 check=True).stdout.strip()
        print(f"{mode:8} {count} kernels: {seconds} s")
