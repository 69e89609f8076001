"""What explaining costs a render: each explained scene against the same scene without its
explainer and overlay (the same world, size, frame rate and length), measured in the same run.

    .venv/bin/python benchmarks/explained_render.py [--quality h] [--seconds 2] [--scenes bounding_volumes]

Each render writes an mp4 to a temporary folder through collisim.pipeline.render, best of
`repeats`; a short render of each first, so compiling and typesetting are not counted. Prints
seconds and frames a second of both and their ratio (the target: under 2).
"""
import argparse
import tempfile
import time
from pathlib import Path

import collisim


def plain(scene):
    """The scene with nothing explained: no explainer, no overlay, no counters (its chapters'
    and panels' scenes too)."""
    if scene.chapters:
        return scene.replace(chapters=[plain(chapter) for chapter in scene.chapters])
    if scene.panels:
        return scene.replace(panels=[collisim.Panel(plain(p.scene), p.title) for p in scene.panels])
    render = scene.render.__class__(**{**vars(scene.render), "explainer": None, "overlay": None, "counters": {}})
    return scene.replace(render=render)


def timed(scene, folder, quality, seconds, repeats) -> float:
    scene = scene.with_options(seconds=seconds)   # a scene of chapters: its video cut there
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        collisim.pipeline.render(scene, Path(folder) / "out.mp4", quality=quality)
        best = min(best, time.perf_counter() - start)
    return best


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--quality", default="h")
    parser.add_argument("--seconds", type=float, default=2.0)
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--scenes", nargs="+", default=["frame_rate", "single_bounce", "two_bodies", "teacher_drop",
                                                          "tunneling", "broadphase_six", "raycast", "collision_map",
                                                          "polygons", "bounding_volumes"])
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        for name in args.scenes:
            explained = collisim.load_scene(name)
            bare = plain(collisim.load_scene(name))
            for scene in (explained, bare):   # compile and typeset first
                timed(scene, folder, "l", 0.3, 1)
            frames = int(round(args.seconds * {"l": 15, "m": 30, "h": 60, "k": 60}[args.quality]))
            with_it = timed(explained, folder, args.quality, args.seconds, args.repeats)
            without = timed(bare, folder, args.quality, args.seconds, args.repeats)
            print(f"{name} -q{args.quality} {args.seconds:g} s: explained {with_it:.2f} s ({frames / with_it:.0f} fps), "
                  f"plain {without:.2f} s ({frames / without:.0f} fps), ratio {with_it / without:.2f}", flush=True)


if __name__ == "__main__":
    main()
