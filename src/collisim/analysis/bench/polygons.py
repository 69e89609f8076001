"""`collisim bench polygons`: the polygons scene, a step of collisim against a step of plain pymunk.

The world is scenes/polygons.py (60 bodies: boxes, triangles, hexagons and balls falling into a
pile under gravity, e = 0.3, μ = 0.4). collisim's discrete engine (DiscreteStepper, one step a
frame, as the scene renders) and plain pymunk (reference/plain_pymunk.py: the Space a user
would build for the same World, pymunk.Poly and pymunk.Circle bodies with the World's masses and
moments, Chipmunk's defaults, no callbacks, space.step alone) each advance their own copy of
the world from its start, in the same run.

The scene changes as it runs: for about two seconds the bodies fall and tumble (few contacts),
then they lie in a pile (many resting contacts, which is where a contact solver spends its
time). So the time is split into phases by simulated time, and each phase is reported on its
own. Every repeat starts both engines afresh and advances them in alternating blocks of
BLOCK_STEPS steps, so a burst of load from elsewhere on the machine lands on both; its ratio
is collisim's time over pymunk's for the same steps. Compilation is done before (one warm-up
run of a few steps). The table gives the median milliseconds per step of each engine and the
range of the ratio over the repeats, and then where collisim's step spends its time (its own
per-phase profile, engine/profile.py, summed over the repeats).

    python -m collisim.analysis.bench.polygons [--seconds 8] [--repeats 3]

`collisim bench polygons --scene bounding_volumes` times another scene of one world the same
way, whole (its falling and pile phases are the polygons scene's).
"""
from __future__ import annotations

import argparse
import time

import numpy as np

BLOCK_STEPS = 30          # steps per timed block: half a simulated second at 60 fps
FALLING_SECONDS = 2.0     # the bodies are in the air until about here; a pile afterwards


def load_world(name: str = "polygons"):
    """(World, fps) of a scene with one world (by default scenes/polygons.py)."""
    from collisim.model.scenefile import load_scene
    scene = load_scene(name)
    if scene.world is None:
        raise ValueError(f"scene '{name}' is made of panels or chapters; bench polygons needs one world")
    return scene.world, scene.fps


def steppers(world, fps: float, profile=None) -> dict:
    """{name: advance(steps) -> wall seconds} for both engines on fresh copies of `world`;
    collisim's phases add into `profile` (an engine Profile) if given."""
    from collisim.analysis.reference.plain_pymunk import PlainPymunk
    from collisim.engine.discrete import DiscreteStepper

    collisim_step = DiscreteStepper(world, fps, 1, "auto", profile)
    plain = PlainPymunk(world)

    def advance_collisim(steps: int) -> float:
        start = time.perf_counter()
        collisim_step.run(steps)
        return time.perf_counter() - start

    return {"collisim": advance_collisim, "pymunk": lambda steps: plain.time_steps(fps, steps)}


def phases(seconds: float, falling: bool = True) -> dict:
    """{phase name: (first, last) simulated seconds}: falling, pile (if the run reaches it), all;
    without `falling` (a scene other than polygons) the whole scene only."""
    if not falling:
        return {"whole scene": (0.0, seconds)}
    split = min(FALLING_SECONDS, seconds)
    found = {"falling": (0.0, split)}
    if seconds > split:
        found["pile"] = (split, seconds)
    found["whole scene"] = (0.0, seconds)
    return found


def time_once(world, fps: float, seconds: float, profile=None) -> dict:
    """One repeat: {engine: (block start times (B,), wall seconds per block (B,), steps per block (B,))}."""
    advance = steppers(world, fps, profile)
    total = max(1, int(round(seconds * fps)))
    starts = np.arange(0, total, BLOCK_STEPS)
    counts = np.minimum(BLOCK_STEPS, total - starts)
    spent = {name: np.empty(len(starts)) for name in advance}
    for b, steps in enumerate(counts):
        for name, step in advance.items():
            spent[name][b] = step(int(steps))
    return {name: (starts / fps, spent[name], counts) for name in advance}


def run(seconds: float = 8.0, repeats: int = 3, world=None, fps=None, falling: bool = True) -> tuple[list[dict], dict]:
    """(rows, profile): rows {phase, collisim_ms, pymunk_ms (medians per step over repeats),
    ratio_low, ratio_high, ratios} for each phase of the polygons scene (or of `world` at `fps`),
    and collisim's seconds per phase of its step over all the repeats."""
    from collisim.engine.profile import Profile
    if not seconds > 0 or int(repeats) != repeats or repeats < 1:
        raise ValueError("seconds must be > 0 and repeats a whole number >= 1")
    if world is None:
        world, fps = load_world()
    for advance in steppers(world, fps).values():   # compile (or load the cached kernels)
        advance(2)
    profile = Profile()
    runs = [time_once(world, fps, seconds, profile) for _ in range(int(repeats))]
    rows = []
    for name, (first, last) in phases(seconds, falling).items():
        per_step = {engine: [] for engine in runs[0]}
        for timed in runs:
            for engine, (starts, spent, counts) in timed.items():
                inside = (starts >= first - 1e-9) & (starts < last - 1e-9)
                per_step[engine].append(spent[inside].sum() / max(1, counts[inside].sum()))
        ratios = np.array(per_step["collisim"]) / np.array(per_step["pymunk"])
        rows.append(dict(phase=f"{name} ({first:g}-{last:g} s)",
                         collisim_ms=1e3 * float(np.median(per_step["collisim"])),
                         pymunk_ms=1e3 * float(np.median(per_step["pymunk"])), ratio_low=float(ratios.min()),
                         ratio_high=float(ratios.max()), ratios=ratios.tolist()))
    return rows, dict(profile.seconds)


def format_rows(rows: list[dict], bodies: int, profile: dict | None = None, scene: str = "polygons") -> str:
    lines = [f"{scene} scene, {bodies} bodies, one step a frame at 60 fps; "
             f"ratio = collisim step / plain pymunk step (range over {len(rows[0]['ratios'])} repeats)",
             f"{'phase':<24} {'collisim ms/step':>16} {'pymunk ms/step':>15} {'ratio':>13}"]
    for row in rows:
        lines.append(f"{row['phase']:<24} {row['collisim_ms']:>16.3f} {row['pymunk_ms']:>15.3f} "
                     f"{row['ratio_low']:>6.2f}-{row['ratio_high']:<6.2f}".rstrip())
    total = sum((profile or {}).values())
    if total > 0:
        shares = ", ".join(f"{phase} {100 * spent / total:.0f} %" for phase, spent in
                           sorted(profile.items(), key=lambda item: -item[1]) if spent >= 0.005 * total)
        lines.append(f"collisim's step by phase: {shares}")
    return "\n".join(lines)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m collisim.analysis.bench.polygons",
                                     description="the polygons scene: collisim's step against plain pymunk's")
    parser.add_argument("--seconds", type=float, default=8.0, help="simulated seconds per repeat (the scene's 8)")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    world, fps = load_world()
    rows, profile = run(args.seconds, args.repeats, world, fps)
    print(format_rows(rows, world.n, profile))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
