"""SHA-256 of the np.save bytes of a few runs' positions, velocities, angles and events, to
check that a change to how kernels compile (typing, arguments, options) leaves every byte the
same. Run before and after and diff the output:

    python benchmarks/trajectory_hashes.py [SCENE ...] > before.txt
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


if __name__ == "__main__":
    main([run for run in RUNS if run[0] in sys.argv[1:]] or RUNS)   # optionally only the scenes named
