"""SHA-256 of the np.save bytes of a few runs' positions, velocities, angles and events, to
check that a change to how kernels compile (typing, arguments, options) leaves every byte the
same. Run before and after and diff the output:

    python benchmarks/trajectory_hashes.py [SCENE ...] > before.txt
    python benchmarks/trajectory_hashes.py ccd > before.txt   # the event-driven method's cases

`ccd` hashes the event loop's own cases instead: the slow, dense and fast gases at 1 000 (1 s)
and the dense gas at 10 000 (0.3 s), 200-ball piles at e = 0, 0.5 and 0.9 (6 s), particles_250
settling under gravity (10 s) and as a gas (4 s), and collision_map's and tunneling's panels.
"""
import hashlib
import io
import sys

import numpy as np

from collisim import simulate
from collisim.model.scenefile import load_scene

# (scene, method: "discrete", "ccd", "discrete xK BROADPHASE", or "own" for a scene of panels or chapters, seconds)
RUNS = [("particles_250", "discrete", 4.0), ("particles_250", "ccd", 4.0), ("polygons", "discrete", 4.0),
        ("particles_250", "discrete x4 grid", 2.0), ("collision_map", "own", 2.0), ("tunneling", "own", 2.0)]


def flat(runs):
    """The trajectories of a run: one, or those of its panels and chapters in order."""
    if isinstance(runs, list):
        return [t for run in runs for t in flat(run)]
    return [runs]


def digest(*arrays) -> str:
    h = hashlib.sha256()
    for a in arrays:
        buffer = io.BytesIO()
        np.save(buffer, np.ascontiguousarray(a))
        h.update(buffer.getvalue())
    return h.hexdigest()[:16]


def main(runs=RUNS) -> None:
    for name, method, seconds in runs:
        words = method.split()
        options = {"method": None if words[0] == "own" else words[0], "seconds": seconds}
        if len(words) > 1:
            options.update(substeps=int(words[1][1:]), broadphase=words[2])
        for t in flat(simulate(load_scene(name).with_options(**options))):
            e = t.events
            print(f"{name:<14} {method:<17} positions {digest(t.positions)} velocities {digest(t.velocities)} "
                  f"angles {digest(t.angles, t.angular_velocities)} "
                  f"events {digest(e.time, e.kind, e.i, e.j, e.impulse, e.point)} ({len(e.time)})", flush=True)


def show(name, t) -> None:
    e = t.events
    print(f"{name:<22} positions {digest(t.positions)} velocities {digest(t.velocities)} "
          f"events {digest(e.time, e.kind, e.i, e.j, e.impulse, e.point)} ({len(e.time)}) "
          f"approximate {int(t.approximate.sum())}", flush=True)


def main_ccd() -> None:
    """The event loop's cases (module docstring)."""
    import collisim
    from collisim.analysis.bench.workloads import WORKLOADS
    from ccd_settling import G, pile_world
    for gas, n, seconds in (("slow_gas", 1000, 1.0), ("dense_gas", 1000, 1.0), ("fast_gas", 1000, 1.0),
                            ("dense_gas", 10000, 0.3)):
        show(f"{gas} {n}", simulate(WORKLOADS[gas](n=n).replace(seconds=seconds, method="ccd")))
    for e in (0.0, 0.5, 0.9):
        show(f"pile e={e}", simulate(collisim.Scene(world=pile_world(e, seed=1), fps=60, seconds=6.0, method="ccd")))
    gas = load_scene("particles_250")
    settling = gas.world.copy(gravity=(0.0, -G), restitution=0.8)
    show("settling", simulate(gas.replace(world=settling, seconds=10.0, method="ccd")))
    show("particles_250", simulate(gas.replace(seconds=4.0, method="ccd")))
    for name in ("collision_map", "tunneling"):
        for k, t in enumerate(flat(simulate(load_scene(name).with_options(seconds=2.0)))):
            show(f"{name} {k}", t)


if __name__ == "__main__":
    if sys.argv[1:] == ["ccd"]:
        main_ccd()
    else:
        main([run for run in RUNS if run[0] in sys.argv[1:]] or RUNS)   # optionally only the scenes named
