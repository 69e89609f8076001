"""Stills of every chapter of the tutorial scenes at -ql and -qh, for the README.

    .venv/bin/python tools/stills.py                 # all tutorial scenes into docs/stills/
    .venv/bin/python tools/stills.py broadphase_six  # one scene
    .venv/bin/python tools/stills.py --table         # the README's "Stills" table

Each still is a frame of the chapter at a moment where its explanation is complete (MOMENTS:
the share of the chapter's frames, 0.9 unless given). The timeline is walked frame by frame as
the video plays (so trails, counters and latched events build up), at the quality's frame size;
-qh is walked at 15 fps rather than 60 (the same pictures, a quarter of the frames to draw).
PNGs are written with a 128-colour palette and optimised, so the folder stays a few MB.
"""
from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from PIL import Image

import collisim
from collisim.render.timeline import Timeline

SCENES = ("frame_rate", "single_bounce", "two_bodies", "tunneling", "broadphase_six", "teacher_drop", "raycast",
          "collision_map")
QUALITIES = ("l", "h")
WALK_FPS = 15
# the share of each chapter's frames at which its still is taken (default 0.9)
MOMENTS = {"broadphase_six": (0.62, 0.64, 0.65, 0.6, 0.66, 0.35), "two_bodies": (0.5,), "tunneling": (0.95, 0.5, 0.9),
           "single_bounce": (0.6,), "teacher_drop": (0.6,)}
CHAPTERS = {
    "frame_rate": ("15 and 60 fps side by side", "ghosts and linear interpolation"),
    "single_bounce": ("update, detection, response",),
    "two_bodies": ("the impact, frozen: line of centres, masses, velocities",),
    "tunneling": ("the easy remedies: slower, more frames", "discrete at 1 and 4 substeps against ccd",
                  "solving for t_c over a frozen frame"),
    "broadphase_six": ("brute force: all 15 pairs", "sweep and prune: the sorted walk",
                       "uniform grid: cells, counts, memory", "kd-tree: median splits", "BVH: build and traversal",
                       "narrow phase: the exact test"),
    "teacher_drop": ("a teacher's scene from the README",),
    "raycast": ("rays from a sensor, a missile's step",),
    "collision_map": ("a painted level, discrete and ccd",),
}
OUT = Path(__file__).resolve().parents[1] / "docs" / "stills"


def chapter_frames(plan, name) -> list:
    """The video frame of each chapter's still."""
    starts = np.cumsum([0] + [c.frames for c in plan.chapters])
    shares = MOMENTS.get(name, ())
    return [int(starts[k] + round((shares[k] if k < len(shares) else 0.9) * (c.frames - 1)))
            for k, c in enumerate(plan.chapters)]


def stills(name: str, quality: str) -> list:
    """(chapter index, RGB image) for every chapter of scene `name` at `quality`."""
    scene = collisim.load_scene(name)
    size = collisim.pipeline.plan(scene, quality=quality).size
    plan = collisim.pipeline.plan(scene, size=size, fps=WALK_FPS)
    timeline = Timeline(plan.chapters, plan.size, plan.fps)
    canvas = np.empty((plan.size[1], plan.size[0], 3), np.uint8)
    wanted, found = chapter_frames(plan, name), []
    for frame in range(max(wanted) + 1):
        timeline.draw(canvas, frame)
        if frame in wanted:
            found.append((wanted.index(frame), canvas[:, :, ::-1].copy()))
    return found


def save(image: np.ndarray, path: Path) -> None:
    picture = Image.fromarray(image).quantize(colors=128, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.NONE)
    picture.save(path, optimize=True)


def table() -> str:
    """The README's table: scene, chapter, the -ql and -qh stills."""
    rows = ["| scene | chapter | -ql (854x480) | -qh (1920x1080) |", "| --- | --- | --- | --- |"]
    for name in SCENES:
        for k, title in enumerate(CHAPTERS[name]):
            low, high = (f"docs/stills/{name}_{k + 1}_{q}.png" for q in QUALITIES)
            rows.append(f"| `{name}` | {k + 1}. {title} | <img src=\"{low}\" width=\"300\"> "
                        f"| <a href=\"{high}\"><img src=\"{high}\" width=\"300\"></a> |")
    return "\n".join(rows)


def main(names) -> None:
    OUT.mkdir(parents=True, exist_ok=True)
    for name in names:
        for quality in QUALITIES:
            for chapter, image in stills(name, quality):
                path = OUT / f"{name}_{chapter + 1}_{quality}.png"
                save(image, path)
                print(f"wrote {path.relative_to(OUT.parents[1])} ({path.stat().st_size // 1024} KB)")


if __name__ == "__main__":
    if sys.argv[1:] == ["--table"]:
        print(table())
    else:
        main(sys.argv[1:] or SCENES)
