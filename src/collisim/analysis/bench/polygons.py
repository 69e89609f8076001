"""`collisim bench polygons`: a step of collisim against a step of plain pymunk and of Box2D 2.3.

The world is scenes/polygons.py by default (60 bodies: boxes, triangles, hexagons and balls
falling into a pile under gravity, e = 0.3, μ = 0.4), another scene of one world (`--scene
bounding_volumes`), or a pyramid of unit boxes (workloads.py: `--scene pyramid40`, 820 boxes in
one pyramid of base 40, and `--scene pyramids10`, ten pyramids of base 10; e = 0, μ = 0.6).
Each contender advances its own copy of the world from its start, in the same run:

* collisim: the discrete engine (DiscreteStepper, one step a frame, as a scene renders), which
  puts bodies at rest to sleep by default;
* pymunk: plain pymunk (reference/plain_pymunk.py: pymunk.Poly and pymunk.Circle bodies with the
  World's masses and moments, each shape's elasticity and friction √e and √μ so that every
  pair meets with the World's e and μ, Chipmunk's defaults, no callbacks, no sleeping);
* pymunk sleeping: the same Space with `sleep_time_threshold` = SLEEP_SECONDS, Chipmunk's
  sleeping on (pymunk's default is off), a line of its own;
* Box2D 2.3: reference/box2d_world.py, a b2World built as a Box2D user would (every fixture the
  World's μ and e, which Box2D mixes as √(μa·μb) and max(ea, eb), so pairs meet with them),
  `Step(dt, 8, 3)`, its defaults (it sleeps); only its steps are timed. Without Box2D installed
  its line says so (BOX2D_MISSING) and the rest runs.

The scene changes as it runs: in the polygons scene the bodies fall and tumble for about two
seconds (few contacts), then lie in a pile (many resting contacts, which is where a contact
solver spends its time); a pyramid stands from the start. So the time is split into phases by
simulated time and each phase is reported on its own: falling, pile and whole for the polygons
scene, the first second (everything awake in every engine) and the whole for the others.
Every repeat starts the engines afresh and advances them in alternating blocks of BLOCK_STEPS
steps, so a burst of load from elsewhere on the machine lands on all; its ratios are
collisim's time over each other's for the same steps. Compilation is done before (one warm-up
run of a few steps). The table gives the median milliseconds per step of each engine, the range
of collisim's ratio to each over the repeats, the bodies each engine has asleep at the end, and
where collisim's step spends its time (its own per-phase profile, engine/profile.py, summed over
the repeats).

A last line gives the cost of a step of the world fully asleep (asleep_cost): each engine that
sleeps (collisim, pymunk sleeping, Box2D 2.3) is run on a fresh copy until every body sleeps,
then timed over ASLEEP_STEPS steps in alternating blocks of simulate's BLOCK_FRAMES, once a
repeat. collisim logs the sleepers' support every step and returns each block as a render's
stream gets it: frames of a world asleep are one state repeated (engine/idle.py). "collisim
storing" is the same step writing every frame into new rows, as simulate() fills the
trajectory it returns (float64 storage): its extra time is the memory, not the step.

    python -m collisim.analysis.bench.polygons [--scene pyramid40] [--seconds 8] [--repeats 3]
"""
from __future__ import annotations

import argparse
import time
import warnings

import numpy as np

BLOCK_STEPS = 30          # steps per timed block: half a simulated second at 60 fps
SLEEP_SECONDS = 0.5       # pymunk sleeping: idle this long, a body sleeps (Box2D's b2_timeToSleep)
BOX2D_MISSING = "Box2D 2.3 not installed (pip install box2d)"
FALLING_SECONDS = 2.0     # the bodies are in the air until about here; a pile afterwards
ASLEEP_STEPS = 640        # steps timed a repeat once every body sleeps: ten of simulate's blocks
ASLEEP_BY = 20.0          # simulated seconds an engine is given to put every body to sleep


def load_world(name: str = "polygons"):
    """(World, fps) of a scene with one world (by default scenes/polygons.py)."""
    from collisim.model.scenefile import load_scene

    from .workloads import PYRAMIDS
    if name in PYRAMIDS:
        return PYRAMIDS[name](), 60.0
    scene = load_scene(name)
    if scene.world is None:
        raise ValueError(f"scene '{name}' is made of panels or chapters; bench polygons needs one world")
    return scene.world, scene.fps


def contenders(world, fps: float, profile=None) -> dict:
    """{name: engine} on fresh copies of `world`: each engine has advance(steps) -> wall seconds
    and asleep() -> bodies asleep; collisim's phases add into `profile` (an engine Profile)."""
    from collisim.analysis.reference.plain_pymunk import PlainPymunk
    from collisim.engine.discrete import DiscreteStepper

    engines = {"collisim": CollisimEngine(DiscreteStepper(world, fps, 1, "auto", profile)),
               "pymunk": ReferenceEngine(PlainPymunk(world), fps),
               "pymunk sleeping": ReferenceEngine(PlainPymunk(world, sleep_time_threshold=SLEEP_SECONDS), fps)}
    if box2d_missing() is None:
        from collisim.analysis.reference.box2d_world import Box2DWorld
        engines["Box2D 2.3"] = Box2DEngine(Box2DWorld(world, fps))
    return engines


def box2d_missing() -> str | None:
    """None when Box2D 2.3 imports, else the line to print instead of its figures. (Imported
    without the notes its SWIG types give Python 3.12's import machinery.)"""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        try:
            import Box2D  # noqa: F401
        except ImportError:
            return BOX2D_MISSING
    return None


def _timed(step, steps: int) -> float:
    """The seconds step(steps) takes."""
    start = time.perf_counter()
    step(steps)
    return time.perf_counter() - start


class CollisimEngine:
    """collisim's discrete engine (a DiscreteStepper), timed around its run; storing: into new
    rows of positions and velocities, as simulate() writes its trajectory."""
    def __init__(self, stepper, storing: bool = False):
        self.stepper, self.storing = stepper, storing

    def advance(self, steps: int) -> float:
        if not self.storing:
            return _timed(self.stepper.run, steps)
        n = len(self.stepper.bodies.positions)
        return _timed(lambda count: self.stepper.run(count, (np.empty((count, n, 2)), np.empty((count, n, 2)))), steps)

    def asleep(self) -> int:
        return int(np.count_nonzero(self.stepper.sleep.asleep))

    def positions(self) -> np.ndarray:
        return self.stepper.bodies.positions.copy()


class ReferenceEngine:
    """Plain pymunk, timed by its own time_steps (space.step calls alone)."""
    def __init__(self, reference, fps: float):
        self.reference, self.fps = reference, fps

    def advance(self, steps: int) -> float:
        return self.reference.time_steps(self.fps, steps)

    def asleep(self) -> int:
        return self.reference.asleep()

    def positions(self) -> np.ndarray:
        return self.reference.state()[0]


class Box2DEngine:
    """Box2D 2.3 (a Box2DWorld), timed around its steps."""
    def __init__(self, reference):
        self.reference = reference

    def advance(self, steps: int) -> float:
        return _timed(self.reference.step, steps)

    def asleep(self) -> int:
        return sum(not body.awake for body in self.reference.bodies)

    def positions(self) -> np.ndarray:
        return self.reference.positions


def phases(seconds: float, falling: bool = True) -> dict:
    """{phase name: (first, last) simulated seconds}: falling, pile (if the run reaches it) and all
    for the polygons scene; without `falling` (another world) the first second and all."""
    split = min(FALLING_SECONDS if falling else 1.0, seconds)
    found = {"falling" if falling else "first second": (0.0, split)}
    if falling and seconds > split:
        found["pile"] = (split, seconds)
    found["whole scene"] = (0.0, seconds)
    return found


def time_once(world, fps: float, seconds: float, profile=None) -> tuple[dict, dict]:
    """One repeat: ({engine: (block start times (B,), wall seconds per block (B,), steps per block (B,))},
    {engine: (bodies asleep at the end, the farthest a body's centre ended from its start)})."""
    engines = contenders(world, fps, profile)
    total = max(1, int(round(seconds * fps)))
    starts = np.arange(0, total, BLOCK_STEPS)
    counts = np.minimum(BLOCK_STEPS, total - starts)
    spent = {name: np.empty(len(starts)) for name in engines}
    for b, steps in enumerate(counts):
        for name, engine in engines.items():
            spent[name][b] = engine.advance(int(steps))
    ends = {name: (engine.asleep(), float(np.max(np.hypot(*(engine.positions() - world.positions).T), initial=0.0)))
            for name, engine in engines.items()}
    return {name: (starts / fps, spent[name], counts) for name in engines}, ends


def run(seconds: float = 8.0, repeats: int = 3, world=None, fps=None, falling: bool = True) -> tuple[list[dict], dict]:
    """(rows, extra): rows {phase, ms: {engine: median ms per step over repeats}, ratios: {engine:
    [collisim / engine, one a repeat]}} for each phase of the polygons scene (or of `world` at
    `fps`); extra {"profile": collisim's seconds per phase of its step over all repeats,
    "ends": {engine: (bodies asleep, farthest a body moved) at the end of the last repeat}, "bodies": n}."""
    from collisim.engine.profile import Profile
    if not seconds > 0 or int(repeats) != repeats or repeats < 1:
        raise ValueError("seconds must be > 0 and repeats a whole number >= 1")
    if world is None:
        world, fps = load_world()
    for engine in contenders(world, fps).values():   # compile (or load the cached kernels)
        engine.advance(2)
    profile = Profile()
    runs = [time_once(world, fps, seconds, profile) for _ in range(int(repeats))]
    rows = []
    for name, (first, last) in phases(seconds, falling).items():
        per_step = {engine: [] for engine in runs[0][0]}
        for timed, _ in runs:
            for engine, (starts, spent, counts) in timed.items():
                inside = (starts >= first - 1e-9) & (starts < last - 1e-9)
                per_step[engine].append(spent[inside].sum() / max(1, counts[inside].sum()))
        ours = np.array(per_step["collisim"])
        rows.append(dict(phase=f"{name} ({first:g}-{last:g} s)",
                         ms={engine: 1e3 * float(np.median(times)) for engine, times in per_step.items()},
                         ratios={engine: (ours / np.array(times)).tolist() for engine, times in per_step.items()
                                 if engine != "collisim"}))
    return rows, dict(profile=dict(profile.seconds), ends=runs[-1][1], bodies=world.n)


def format_rows(rows: list[dict], extra: dict, scene: str = "polygons") -> str:
    engines = list(rows[0]["ms"])
    others = [engine for engine in engines if engine != "collisim"]
    lines = [f"{scene}: {extra['bodies']} bodies, one step a frame at 60 fps, ms a step (median) and "
             f"collisim / each (range over {len(rows[0]['ratios']['pymunk'])} repeats); materials matched "
             f"(every pair meets with the world's e and mu)",
             f"{'phase':<24} {'collisim':>9}" + "".join(f" {engine:>26}" for engine in others)]
    for row in rows:
        cells = "".join(f" {row['ms'][engine]:>9.3f} ({min(row['ratios'][engine]):.2f}-"
                        f"{max(row['ratios'][engine]):.2f})".rjust(27) for engine in others)
        lines.append(f"{row['phase']:<24} {row['ms']['collisim']:>9.3f}{cells}")
    lines.append("at the end, bodies asleep / farthest a body moved from its start: " + ", ".join(
        f"{engine} {asleep} / {moved:.3g}" for engine, (asleep, moved) in extra["ends"].items()))
    if box2d_missing() is not None:
        lines.append(box2d_missing())
    profile = extra["profile"]
    total = sum(profile.values())
    if total > 0:
        shares = ", ".join(f"{phase} {100 * spent / total:.0f} %" for phase, spent in
                           sorted(profile.items(), key=lambda item: -item[1]) if spent >= 0.005 * total)
        lines.append(f"collisim's step by phase: {shares}")
    return "\n".join(lines)


def asleep_cost(world, fps: float, repeats: int = 3) -> dict:
    """A step of the world fully asleep, in each engine that sleeps (the module): {"us": {engine:
    [microseconds a step, one a repeat]}, "asleep": {engine: (bodies asleep when timed, simulated
    seconds it took)}, "bodies": n}."""
    from collisim.engine.discrete import DiscreteStepper
    from collisim.engine.simulate import BLOCK_FRAMES
    engines = {name: engine for name, engine in contenders(world, fps).items() if name != "pymunk"}
    engines["collisim storing"] = CollisimEngine(DiscreteStepper(world, fps, 1, "auto"), storing=True)
    settled = {name: _settle(engine, world.n, fps, BLOCK_FRAMES) for name, engine in engines.items()}
    us = {name: [] for name in engines}
    for _ in range(int(repeats)):
        spent = dict.fromkeys(engines, 0.0)
        for _ in range(ASLEEP_STEPS // BLOCK_FRAMES):
            for name, engine in engines.items():
                spent[name] += engine.advance(BLOCK_FRAMES)
        for name in engines:
            us[name].append(1e6 * spent[name] / (ASLEEP_STEPS // BLOCK_FRAMES * BLOCK_FRAMES))
    return dict(us=us, asleep=settled, bodies=world.n)


def _settle(engine, n: int, fps: float, block: int) -> tuple[int, float]:
    """Advance an engine in blocks until all n bodies sleep, or ASLEEP_BY seconds: (asleep, seconds)."""
    steps = 0
    while engine.asleep() < n and steps < ASLEEP_BY * fps:
        engine.advance(block)
        steps += block
    return engine.asleep(), steps / fps


def format_asleep(found: dict) -> str:
    us, n = found["us"], found["bodies"]
    ours = np.array(us["collisim"])
    cells = [f"{name} {np.median(times):.2f}" for name, times in us.items() if name.startswith("collisim")] + [
        f"{name} {np.median(times):.2f} ({min(ours / np.array(times)):.2f}-{max(ours / np.array(times)):.2f})"
        for name, times in us.items() if not name.startswith("collisim")]
    asleep = ", ".join(f"{name} {k} / {n} after {seconds:.1f} s" for name, (k, seconds) in found["asleep"].items())
    return (f"fully asleep: us a step (median) and collisim / each (range over {len(ours)} repeats): "
            + ", ".join(cells) + f"\nbodies asleep when timed: {asleep}")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m collisim.analysis.bench.polygons",
                                     description="the polygons scene: collisim's step against plain pymunk's")
    parser.add_argument("--seconds", type=float, default=8.0, help="simulated seconds per repeat (the scene's 8)")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--scene", default="polygons", help="pyramid40, pyramids10 or a scene of one world")
    args = parser.parse_args(argv)
    world, fps = load_world(args.scene)
    rows, extra = run(args.seconds, args.repeats, world, fps, falling=args.scene == "polygons")
    print(format_rows(rows, extra, args.scene))
    print(format_asleep(asleep_cost(world, fps, args.repeats)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
