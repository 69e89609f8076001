"""Benchmark: render throughput for the job the video quotes.

The video rendered 100 particles at 60 fps for one minute: 1 h 40 min with naive pair checks,
3 min with sweep and prune. Here the same job renders at 1280x720 and its time is split into
simulate, draw and encode (the encoder runs on its own thread, overlapping the drawing). The
floor is the time to encode the same frames alone: frames are drawn ahead, in batches, outside
the clock, then only the encoding is timed. A render can be no faster than its encoder, so
render / floor is the overhead of everything else.

Memory: particles_250 rendered for 30 s and for 2 minutes in fresh processes, peak resident
memory of each; the engine streams blocks of frames, so the peak should not grow with length.

Stills (`still_figures`): -s, the last frame drawn alone (render/player.py: Timeline.draw_alone),
against the whole video it ends, in the same run: the video job at 720p, and broadphase_six at
-ql (chapters, frozen builds, an explainer; cut to the job's length).

Drawing (`drawing_ms`, `many_particles_figures`; run(drawing=True) adds both to render.json, and
`python -m collisim.analysis.bench.render` prints them): the particles_250 size mix scaled to
250, 25 000 and 250 000 particles (the box grows with the count, so the discs shrink from 8-18 px
to under a pixel at 720p), drawn at 1280x720 and 1920x1080 by the compiled rasterizer
(render/splat.py) and by the former one cv2.circle call per disc, in the same run, alternating,
milliseconds per frame over repeats. Then a whole render of 25 000 particles at 720p against the
encode-only floor of the same frames, and the same render with the former drawing.
"""
from __future__ import annotations

import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import cv2
import numpy as np

import collisim
from collisim import palette
from collisim.core.files import write_text
from collisim.gas import lattice_gas
from collisim.io.writers import open_writer
from collisim.palette import default_colors
from collisim.pipeline import scene_chapters
from collisim.render import raster
from collisim.render.timeline import Timeline
from collisim.render.view import View

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


def run(out_dir: Path, seconds: float = 60.0, memory: bool = True, progress: bool = True,
        drawing: bool = False) -> dict:
    """Measure the video's job; write render.json; return the figures. drawing: also the
    drawing figures (drawing_ms and many_particles_figures, a few minutes more)."""
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    scene = video_job(seconds)
    steps = ["warm up", "simulate (brute)", "simulate (sweep_prune)", "render", "encode only", "stills", "memory",
             "drawing"]
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
        say(steps[5])
        figures["stills"] = still_figures(folder, scene, wall)
        if memory:
            say(steps[6])
            figures["peak_memory_mb"] = {"30 s": peak_memory_mb(30, folder), "120 s": peak_memory_mb(120, folder)}
        if drawing:
            say(steps[7])
            figures["drawing"] = {"per_frame": drawing_ms(), "many_particles": many_particles_figures(folder)}
    write_text(out_dir / "render.json", json.dumps(figures, indent=2))
    return figures


# --- stills ----------------------------------------------------------------------------------------

def still_seconds(scene, folder: Path, size=None, quality=None) -> float:
    """Wall seconds of -s: the scene's last frame, simulated to and drawn alone, as a PNG."""
    start = time.perf_counter()
    collisim.render(scene, folder / "still.png", size, quality=quality, last_frame=True)
    return time.perf_counter() - start


def still_figures(folder: Path, job: collisim.Scene, job_render_seconds: float) -> list:
    """-s against the whole render it ends, each pair in this run: the video job at 720p (its
    render timed by run), and broadphase_six at -ql rendered here, cut to the job's length when
    that is shorter (its chapters run 83 s)."""
    rows = [{"scene": job.name, "size": list(SIZE), "still_seconds": still_seconds(job, folder, SIZE),
             "video_seconds": job_render_seconds}]
    explained = collisim.load_scene("broadphase_six")
    explained = explained.with_options(seconds=min(job.seconds, explained.seconds))
    collisim.render(explained, folder / "warm_still.png", quality="l", png_frame=0)   # its typesetting, once
    start = time.perf_counter()
    collisim.render(explained, folder / "explained.mp4", quality="l")
    video = time.perf_counter() - start
    rows.append({"scene": explained.name, "size": [854, 480], "still_seconds": still_seconds(explained, folder,
                                                                                            quality="l"),
                 "video_seconds": video})
    return rows


def format_stills(rows: list) -> str:
    return "\n".join(f"-s (the last frame alone) {row['scene']} at {row['size'][0]}x{row['size'][1]}: "
                     f"{row['still_seconds']:.2f} s, its whole video {row['video_seconds']:.2f} s "
                     f"(x{row['video_seconds'] / row['still_seconds']:.0f})" for row in rows)


# --- drawing ----------------------------------------------------------------------------------------

DRAWING_COUNTS = (250, 25_000, 250_000)
DRAWING_SIZES = ((1280, 720), (1920, 1080))


def drawing_workload(n: int, size=SIZE, seed: int = 1, shuffle: bool = False) -> tuple:
    """particles_250's size mix (radii 0.22/0.32/0.45 in a 32x18 box) scaled to n particles: the
    box grows by sqrt(n / 250), so the particles keep their packing and shrink on screen. Returns
    centres (n, 2) and radii (n,) in pixels of a `size` frame, colours (n, 3) RGB. In lattice
    order (row after row of the lattice, as a gas starts), or shuffled, as a gas mixes."""
    grow = np.sqrt(n / 250)
    box = (0.0, 0.0, 32.0 * grow, 18.0 * grow)
    positions, _, radii = lattice_gas(n, box=box, seed=seed)
    if shuffle:
        order = np.random.default_rng(seed).permutation(n)
        positions, radii = positions[order], radii[order]
    view = View(box, (0, 0, size[0], size[1]))
    return view.to_pixels(positions), view.length(radii), default_colors(radii)


def cv2_circles(canvas, centres_px, radii_px, colors_rgb) -> None:
    """The former raster.draw_circles: one anti-aliased cv2.circle per disc, at 1/16 pixel."""
    centres = raster.fixed(centres_px).tolist()
    radii = raster.fixed(np.maximum(radii_px, 0.5)).tolist()
    colors = np.asarray(colors_rgb)[:, ::-1].tolist()
    for (x, y), r, color in zip(centres, radii, colors):
        cv2.circle(canvas, (x, y), r, color, -1, cv2.LINE_AA, raster.SHIFT)


def _spread(samples) -> dict:
    ms = 1e3 * np.asarray(samples)
    return {"min": float(ms.min()), "median": float(np.median(ms)), "max": float(ms.max()), "runs": len(ms)}


def drawing_ms(counts=DRAWING_COUNTS, sizes=DRAWING_SIZES, repeats: int = 7, old_repeats: int = 3,
               shuffle: bool = False) -> list:
    """Milliseconds to draw one frame's discs, compiled (raster.draw_circles) and former
    (cv2_circles), alternating in the same run; the frame is reset outside the clock. One row per
    size and count: radii in pixels, then min/median/max of each. The former drawing takes
    about a second a frame at 250 000 discs, hence fewer repeats.

    Timed on the wall clock (`*_ms`): from bands.BAND_DISCS discs on, the compiled drawing
    splits the frame's rows between threads, one per core. The process's CPU time is given too
    (`new_cpu_ms`): the work done, whatever the split. On a shared machine the wall clock also
    counts the time other work held a core."""
    rows = []
    for size in sizes:
        background = np.empty((size[1], size[0], 3), np.uint8)
        background[:] = raster.bgr(palette.BACKGROUND)
        canvas = background.copy()
        for n in counts:
            centres, radii, colors = drawing_workload(n, size, shuffle=shuffle)
            raster.draw_circles(canvas, centres, radii, colors)        # compiled before the clock
            new, cpu, old = [], [], []
            for k in range(repeats):
                np.copyto(canvas, background)
                start, start_cpu = time.perf_counter(), time.process_time()
                raster.draw_circles(canvas, centres, radii, colors)
                new.append(time.perf_counter() - start)
                cpu.append(time.process_time() - start_cpu)
                if k < old_repeats:
                    np.copyto(canvas, background)
                    start = time.perf_counter()
                    cv2_circles(canvas, centres, radii, colors)
                    old.append(time.perf_counter() - start)
            new_ms, old_ms = _spread(new), _spread(old)
            rows.append({"size": list(size), "n": n, "radius_px": [float(radii.min()), float(radii.max())],
                         "order": "shuffled" if shuffle else "lattice", "new_ms": new_ms, "new_cpu_ms": _spread(cpu),
                         "old_ms": old_ms, "old_over_new": old_ms["median"] / new_ms["median"]})
    return rows


def many_particles_job(n: int = 25_000, seconds: float = 5.0) -> collisim.Scene:
    """n particles of particles_250's size mix at its packing, 60 fps, in a box scaled to fit."""
    grow = np.sqrt(n / 250)
    box = (0.0, 0.0, 32.0 * grow, 18.0 * grow)
    positions, velocities, radii = lattice_gas(n, box=box, speed=3.0, seed=1)
    world = collisim.World(positions=positions, velocities=velocities, radii=radii, box=box)
    return collisim.Scene(world=world, fps=60, seconds=seconds, broadphase="grid", name=f"gas_{n}")


def many_particles_figures(folder: Path, n: int = 25_000, seconds: float = 5.0, former: bool = True) -> dict:
    """A whole render of many_particles_job at 720p against the encode-only floor of the same
    frames (both after a warm-up render), and, with `former`, the same render drawing discs with
    cv2_circles instead."""
    folder = Path(folder)
    scene = many_particles_job(n, seconds)
    collisim.render(many_particles_job(n, 0.2), folder / "warm_many.mp4", SIZE)
    wall, split = render_seconds(scene, folder)
    floor = encode_only_seconds(scene, folder)
    figures = {"n": n, "frames": scene.frames, "size": list(SIZE), "render_seconds": wall, "split": split,
               "encode_only_seconds": floor, "render_over_encode_only": wall / floor}
    if former:
        compiled = raster.draw_styled_circles
        raster.draw_styled_circles = lambda canvas, centres, style: cv2_circles(canvas, centres, style.radii,
                                                                               style.colors[:, ::-1])
        try:
            old_wall, old_split = render_seconds(scene, folder)
        finally:
            raster.draw_styled_circles = compiled
        figures["former"] = {"render_seconds": old_wall, "split": old_split,
                             "render_over_encode_only": old_wall / floor}
    return figures


def format_drawing(rows: list, many: dict | None = None) -> str:
    lines = ["drawing one frame's discs, wall ms: min / median / max over repeats (compiled: and its CPU ms, "
             "all threads); former / compiled, medians"]
    for row in rows:
        new, cpu, old = row["new_ms"], row["new_cpu_ms"], row["old_ms"]
        lines.append(f"{row['size'][0]}x{row['size'][1]} n={row['n']:>7} r {row['radius_px'][0]:.2f}-"
                     f"{row['radius_px'][1]:.2f} px ({row['order']}): compiled {new['min']:.2f} / "
                     f"{new['median']:.2f} / {new['max']:.2f} (CPU {cpu['min']:.2f} / {cpu['median']:.2f} / "
                     f"{cpu['max']:.2f}), cv2 {old['min']:.1f} / {old['median']:.1f} / {old['max']:.1f}, "
                     f"x{row['old_over_new']:.0f}")
    if many is not None:
        split = many["split"]
        lines.append(f"{many['n']} particles, {many['frames']} frames at {many['size'][0]}x{many['size'][1]}: render "
                     f"{many['render_seconds']:.2f} s (simulate {split['simulate']:.2f}, draw {split['draw']:.2f}, "
                     f"encode {split['encode']:.2f}), encode only {many['encode_only_seconds']:.2f} s, "
                     f"ratio {many['render_over_encode_only']:.2f}")
        if "former" in many:
            former = many["former"]
            lines.append(f"  with the former cv2 drawing: render {former['render_seconds']:.2f} s (draw "
                         f"{former['split']['draw']:.2f}), ratio {former['render_over_encode_only']:.2f}")
    return "\n".join(lines)


def main(argv=None) -> int:
    import argparse
    parser = argparse.ArgumentParser(description="drawing figures: compiled discs against cv2.circle")
    parser.add_argument("--repeats", type=int, default=7)
    parser.add_argument("--old-repeats", type=int, default=3)
    parser.add_argument("--shuffle", action="store_true", help="draw the discs in shuffled order (a mixed gas)")
    parser.add_argument("--seconds", type=float, default=5.0, help="length of the 25 000-particle render")
    parser.add_argument("--no-render", action="store_true", help="only the per-frame drawing figures")
    parser.add_argument("--out", type=Path, default=None, help="also write drawing.json into this folder")
    args = parser.parse_args(argv)
    rows = drawing_ms(repeats=args.repeats, old_repeats=args.old_repeats, shuffle=args.shuffle)
    many = None
    if not args.no_render:
        with tempfile.TemporaryDirectory() as scratch:
            many = many_particles_figures(Path(scratch), seconds=args.seconds)
    print(format_drawing(rows, many))
    if args.out is not None:
        args.out.mkdir(parents=True, exist_ok=True)
        write_text(args.out / "drawing.json", json.dumps({"per_frame": rows, "many_particles": many}, indent=2))
    return 0


if __name__ == "__main__":
    sys.exit(main())
