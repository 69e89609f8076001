"""What numba's compile costs for the width of what kernels hand each other, on one kernel tree.

    python benchmarks/compile_width.py            # 8 sweeps: namedtuples, structrefs, held arrays
    python benchmarks/compile_width.py 24 call    # 24 sweeps, the per-row solve not inlined

The tree is the contact solver's shape: a step calls `sweeps` kernels, each a loop over 4 000
rows calling a per-row solve (LLVM-inlined, as engine kernels handed the state are); every one
is handed the bodies (11 arrays) and the rows (15 arrays) whole. Two ways to hand them:

* tuple: namedtuples of arrays, the kernels compiled without numba's runtime (`_nrt=False`), as
  the engine's are. numba passes a namedtuple to every call flattened into its arrays' fields (7
  to 9 numbers an array), and each kernel unpacks them all, whatever it reads.
* ref: numba's StructRef (numba.experimental.structref), one pointer; its fields are read through
  numba's runtime, so the kernels are compiled with it.
* held: structrefs too, but each sweep reads the arrays it uses out of them once, before its
  loop, and hands the per-row solve those arrays: inside the loop a field read from a structref
  is read from memory again after every store (the compiler cannot tell the store did not
  change it), where a namedtuple's fields are values.

Each case runs in a fresh process without the cache: the seconds of the first call (the
compile), then the best of 7 calls of 10 sweeps (the run), per row solve.
"""
import subprocess
import sys

SOURCE = '''
import sys, time
from collections import namedtuple
import numpy as np
from numba import njit, types
from numba.experimental import structref

MODE, SWEEPS, INLINE = sys.argv[1], int(sys.argv[2]), sys.argv[3] == "inline"
HELD = MODE == "held"
BODY_FIELDS = ["shapes", "positions", "velocities", "angles", "angular_velocities", "accelerations", "radii",
               "masses", "inertias", "vertex_start", "body_vertices"]
ROW_FIELDS = ["i", "j", "kind", "normal", "point_i", "point_j", "depth", "mass_n", "mass_t", "impulse_n",
              "impulse_t", "bias", "restitution", "friction", "relative"]
n, k = 2000, 4000
rng = np.random.default_rng(0)
body_arrays = [np.zeros(n, np.int8), rng.random((n, 2)), rng.random((n, 2)), rng.random(n), rng.random(n),
               np.zeros((n, 2)), rng.random(n) + 0.5, rng.random(n) + 1.0, rng.random(n) + 1.0,
               np.zeros(n + 1, np.int64), np.zeros((1, 2))]
i = rng.integers(0, n, k)
j = (i + 1 + rng.integers(0, n - 1, k)) % n
normal = rng.standard_normal((k, 2))
normal /= np.linalg.norm(normal, axis=1)[:, None]
row_arrays = [i, j, np.zeros(k, np.int64), normal, rng.random((k, 2)), rng.random((k, 2)), rng.random(k) * 0.01,
              rng.random(k) + 0.5, rng.random(k) + 0.5, np.zeros(k), np.zeros(k), np.zeros(k), np.full(k, 0.5),
              np.full(k, 0.3), np.zeros(k)]

if MODE == "tuple":
    bodies = namedtuple("Bodies", BODY_FIELDS)(*body_arrays)
    rows = namedtuple("Rows", ROW_FIELDS)(*row_arrays)
    options = dict(_nrt=False, error_model="numpy")
else:
    class Ref(types.StructRef):
        def preprocess_fields(self, fields):
            return tuple((name, types.unliteral(t)) for name, t in fields)

    class BodiesType(Ref):
        pass

    class RowsType(Ref):
        pass

    class Bodies(structref.StructRefProxy):
        pass

    class Rows(structref.StructRefProxy):
        pass

    structref.register(BodiesType)
    structref.register(RowsType)
    structref.define_proxy(Bodies, BodiesType, BODY_FIELDS)
    structref.define_proxy(Rows, RowsType, ROW_FIELDS)
    bodies, rows = Bodies(*body_arrays), Rows(*row_arrays)   # (their constructors compile here, untimed)
    options = dict(error_model="numpy")


@njit(forceinline=INLINE, **options)
def solve(velocities, masses, first, second, normal, impulse, bias, mass, q, scale):
    i, j = first[q], second[q]
    nx, ny = normal[q, 0], normal[q, 1]
    vn = (velocities[j, 0] - velocities[i, 0]) * nx + (velocities[j, 1] - velocities[i, 1]) * ny
    old = impulse[q]
    new = max(old - (vn + bias[q]) * mass[q] * scale, 0.0)
    impulse[q] = new
    p = new - old
    wi, wj = 1.0 / masses[i], 1.0 / masses[j]
    velocities[i, 0] -= p * nx * wi
    velocities[i, 1] -= p * ny * wi
    velocities[j, 0] += p * nx * wj
    velocities[j, 1] += p * ny * wj
    return abs(p)


@njit(forceinline=INLINE, **options)
def solve_row(b, r, q, scale):
    return solve(b.velocities, b.masses, r.i, r.j, r.normal, r.impulse_n, r.bias, r.mass_n, q, scale)


lines = []
for m in range(SWEEPS):
    lines.append(f"""
@njit(**options)
def sweep{m}(b, r, sweeps):
    total = 0.0
    for s in range(sweeps):
        change = 0.0
        if HELD:
            velocities, masses, first, second = b.velocities, b.masses, r.i, r.j
            normal, impulse, bias, mass = r.normal, r.impulse_n, r.bias, r.mass_n
            for q in range(first.shape[0]):
                change += solve(velocities, masses, first, second, normal, impulse, bias, mass, q, {1.0 + 0.01 * m})
        else:
            for q in range(r.i.shape[0]):
                change += solve_row(b, r, q, {1.0 + 0.01 * m})
        total += change
    return total
""")
calls = "".join(f"    t += sweep{m}(b, r, sweeps)\\n" for m in range(SWEEPS))
lines.append(f"@njit(error_model='numpy')\\ndef step(b, r, sweeps):\\n    t = 0.0\\n{calls}    return t\\n")
exec("".join(lines))
start = time.perf_counter()
step(bodies, rows, 1)
compile_seconds = time.perf_counter() - start
best = 1e9
for _ in range(7):
    start = time.perf_counter()
    step(bodies, rows, 10)
    best = min(best, time.perf_counter() - start)
print(f"compile {compile_seconds:.2f} s, run {best / (SWEEPS * 10 * k) * 1e9:.1f} ns a row solve")
'''


if __name__ == "__main__":
    sweeps = sys.argv[1] if len(sys.argv) > 1 else "8"
    inline = sys.argv[2] if len(sys.argv) > 2 else "inline"
    for mode in ("tuple", "ref", "held"):
        result = subprocess.run([sys.executable, "-c", SOURCE, mode, sweeps, inline], capture_output=True, text=True,
                                check=True).stdout.strip()
        print(f"{mode:6} {sweeps} sweeps ({inline}): {result}")
