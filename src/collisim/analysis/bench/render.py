"""Benchmark: render throughput for the job the video quotes.

The video rendered 100 particles at 60 fps for one minute: 1 h 40 min with naive pair checks,
3 min with sweep and prune. Here the same job renders at 1280x720 and its time is split into
simulate, draw and encode (the encoder runs on its own thread, overlapping the drawing). The
floor is the time to encode the same frames alone: frames are drawn ahead, in batches, outside
the clock, then only the encoding is timed. A render can be no faster than its encoder, so
render / floor is the overhead of everything else.

Memory: particles_250 rendered for 30 s and for 2 minutes in fresh processes, peak resident
memory of each; the engine streams blocks of frames, so the peak should not grow with length.
"""
from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import collisim
from collisim.gas import lattice_gas
from collisim.io.writers import open_writer
from collisim.pipeline import scene_chapters
from collisim.render.player import Timeline

SIZE = (1280, 720)
BATCH = 120   # frames drawn ahead for the encode-only floor (about 330 MB at 720p)


def video_job(seconds: float = 60.0, broadphase: str = "sweep_prune") -> collisim.Scene:
    """100 particles at 60 fps in a 16:9 box, as in the video."""
    box = (0.0, 0.0, 32.0, 18.0)
    positions, velocities, radii = lattice_gas(100, box=box, speed=3.0, seed=1)
    world = collisim.World(positions=positions, velocities=velocities, radii=radii, box=box)
    return collisim.Scene(world=world, fps=60, seconds=seconds, broadphase=broadphase, name="video_job")


def simulate_seconds(scene: collisim.Scene) -> float:
    start = time.perf_counter()
    collisim.simulate(scene)
    return time.perf_counter() - start


def render_seconds(scene: collisim.Scene, folder: Path) -> tuple:
    """Wall seconds of a full render, and its split (simulate, draw, encode)."""
    profile = {}
    start = time.perf_counter()
    collisim.render(scene, folder / "job.mp4", SIZE, profile=profile)
    wall = time.perf_counter() - start
    encode, draw = profile.pop("encode"), profile.pop("draw")
    return wall, {"simulate": sum(profile.values()), "draw": draw, "encode": encode}


def encode_only_seconds(scene: collisim.Scene, folder: Path) -> float:
    """Seconds to encode the scene's frames, drawn beforehand outside the clock."""
    timeline = Timeline(scene_chapters(scene), SIZE, scene.fps)
    batch = np.empty((BATCH, SIZE[1], SIZE[0], 3), np.uint8)
    timed = 0.0
    with open_writer("h264", folder / "floor.mp4", scene.fps, SIZE) as video:
        for first in range(0, scene.frames, BATCH):
            frames = range(first, min(first + BATCH, scene.frames))
            for row, frame in enumerate(frames):
                timeline.draw(batch[row], frame)
            start = time.perf_counter()
            for row in range(len(frames)):
                video.write(batch[row])
            timed += time.perf_counter() - start
        start = time.perf_counter()
    return timed + time.perf_counter() - start   # the encoder drains the queue on exit


MEMORY_PROBE = """
import json, resource, sys, collisim
scene = collisim.load_scene("particles_250").with_options(seconds=float(sys.argv[1]))
collisim.render(scene, sys.argv[2], (640, 360))
print(json.dumps(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss))
"""


def peak_memory_mb(seconds: float, folder: Path) -> float:
    """Peak resident memory (MB) of a fresh process rendering particles_250 for `seconds`."""
    out = subprocess.run([sys.executable, "-c", MEMORY_PROBE, str(seconds), str(folder / f"mem{seconds:g}.mp4")],
                         capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1]) / 1024


def run(out_dir: Path, seconds: float = 60.0, memory: bool = True, progress: bool = True) -> dict:
    """Measure the video's job; write render.json; return the figures."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    scene = video_job(seconds)
    steps = ["warm up", "simulate (brute)", "simulate (sweep_prune)", "render", "encode only", "memory"]
    say = (lambda step: print(f"bench render: {step}", file=sys.stderr)) if progress else (lambda step: None)
    with tempfile.TemporaryDirectory(dir=out_dir) as scratch:
        folder = Path(scratch)
        say(steps[0])
        collisim.render(video_job(0.5), folder / "warm.mp4", SIZE)
        say(steps[1])
        brute = simulate_seconds(scene.replace(broadphase="brute"))
        say(steps[2])
        sweep = simulate_seconds(scene)
        say(steps[3])
        wall, split = render_seconds(scene, folder)
        say(steps[4])
        floor = encode_only_seconds(scene, folder)
        figures = {"frames": scene.frames, "size": list(SIZE), "render_seconds": wall, "split": split,
                   "encode_only_seconds": floor, "render_over_encode_only": wall / floor,
                   "simulate_brute_seconds": brute, "simulate_sweep_prune_seconds": sweep}
        if memory:
            say(steps[5])
            figures["peak_memory_mb"] = {"30 s": peak_memory_mb(30, folder), "120 s": peak_memory_mb(120, folder)}
    (out_dir / "render.json").write_text(json.dumps(figures, indent=2))
    return figures
