"""The `collisim` command: list scenes, render them, compare methods, run the benchmarks.

Bad input gives one line on stderr and exit status 2; never a traceback, never a partial file.
"""
from __future__ import annotations

import argparse
import os
import sys
import time
import warnings
from pathlib import Path

from .broadphase import NAMES as BROAD_PHASES
from .engine import METHODS
from .engine.profile import profile_table
from .io.writers import WRITERS
from .model.scene import RenderSettings
from .model.scene import QUALITY_SIZES
from .model.scenefile import available_scenes, describe_scene_file, load_scene


class OneLineParser(argparse.ArgumentParser):
    """argparse that reports a usage mistake in one line instead of usage + error."""

    def error(self, message):
        self.exit(2, f"collisim: error: {message} (see {self.prog} --help)\n")


def parse_size(text: str) -> tuple:
    try:
        width, height = (int(v) for v in text.lower().split("x"))
    except ValueError:
        raise argparse.ArgumentTypeError(f"size must look like 1280x720, got '{text}'") from None
    return width, height


def build_parser() -> argparse.ArgumentParser:
    parser = OneLineParser(prog="collisim", description="Render collision simulations to video.")
    commands = parser.add_subparsers(dest="command", required=True, parser_class=OneLineParser)
    commands.add_parser("list", help="list the scenes with a one-line description")
    render = commands.add_parser("render", help="render a scene to MP4 (or one frame to PNG)")
    render.add_argument("scene", help="scene name (e.g. single_bounce), path to a scene file, or a saved "
                                      "trajectory (.npz)")
    render.add_argument("--out", type=Path, help="output file (default renders/<scene>.mp4)")
    render.add_argument("--fps", type=float, help="frames per second of the video")
    render.add_argument("--seconds", type=float, help="duration")
    render.add_argument("--size", type=parse_size, help="frame size WxH (default: the scene's, by quality)")
    render.add_argument("--quality", choices=tuple(QUALITY_SIZES), default="m",
                        help="l 480p / m 720p / h 1080p, with matching encoder quality")
    render.add_argument("--codec", choices=tuple(WRITERS), default="h264")
    render.add_argument("--png", type=int, metavar="FRAME", help="write frame FRAME as PNG instead of a video")
    render.add_argument("--method", choices=tuple(METHODS))
    render.add_argument("--substeps", type=int, help="discrete steps per frame")
    render.add_argument("--broadphase", choices=BROAD_PHASES, help="broad phase")
    render.add_argument("--restitution", type=float, help="coefficient of restitution e in [0, 1]")
    render.add_argument("--profile", action="store_true", help="print time per phase at the end")
    render.add_argument("--no-progress", action="store_true", help="no progress bar")
    render.add_argument("--save-trajectory", type=Path, metavar="PATH",
                        help="also write the simulated trajectory to PATH (.npz) (scenes of one world)")
    add_bench_parser(commands)
    compare = commands.add_parser("compare", help="run collisim's methods and pymunk on one scene, one table")
    compare.add_argument("scene", help="scene name or path")
    compare.add_argument("--methods", nargs="+", help="labels such as 'discrete x1' 'discrete x8' ccd 'pymunk x1'")
    compare.add_argument("--seconds", type=float, help="simulated duration")
    compare.add_argument("--json", action="store_true", help="print JSON instead of a table")
    compare.add_argument("--video", type=Path, metavar="PATH",
                         help="also render the compared runs side by side, titled, to PATH")
    return parser


def add_bench_parser(commands) -> None:
    bench = commands.add_parser("bench", help="benchmarks: speed as ratios against references in the same run")
    kinds = bench.add_subparsers(dest="kind", required=True, parser_class=OneLineParser)
    broad = kinds.add_parser("broadphase", help="time per frame of each broad phase against n, with "
                                                "scipy cKDTree and pymunk as reference lines")
    broad.add_argument("--sizes", type=int, nargs="+", default=[100, 300, 1000, 3000, 10000, 30000, 100000])
    broad.add_argument("--repeats", type=int, default=3)
    broad.add_argument("--packing", type=float, default=0.1)
    render = kinds.add_parser("render", help="the video's job (100 particles, 60 fps, 1 min, 720p): "
                                              "simulate, draw and encode against encoding alone; peak memory")
    render.add_argument("--seconds", type=float, default=60.0, help="length of the job")
    render.add_argument("--no-memory", action="store_true", help="skip the peak-memory runs")
    accuracy = kinds.add_parser("accuracy", help="speed against error for discrete, ccd and pymunk on four "
                                                  "workloads, with the Pareto front")
    accuracy.add_argument("--workloads", "--scenes", nargs="+", help="slow_gas dense_gas fast_gas gravity_bounce")
    accuracy.add_argument("--seconds", type=float, default=10.0)
    accuracy.add_argument("--repeats", type=int, default=3)
    segments = kinds.add_parser("segments", help="the discrete step with 2 000 static segments among 18 000 "
                                                 "bodies against the same gas without them")
    segments.add_argument("--bodies", type=int, default=18_000)
    segments.add_argument("--segments", type=int, default=2_000)
    segments.add_argument("--repeats", type=int, default=3)
    for parser in (broad, render, accuracy, segments):
        parser.add_argument("--out", type=Path, default=Path("renders/bench"), help="folder for CSV and PNG")
        parser.add_argument("--no-progress", action="store_true")


def cmd_list(args) -> int:
    scenes = available_scenes()
    width = max((len(name) for name in scenes), default=0)
    for name, path in scenes.items():
        print(f"{name:<{width}}  {describe_scene_file(path)}")
    return 0


def cmd_render(args) -> int:
    from .model.trajectory import load_trajectory
    from .pipeline import render
    from .render.video import output_size

    if str(args.scene).endswith(".npz"):
        source = load_trajectory(args.scene)
        name, fps, frames, base = Path(args.scene).stem, source.fps, source.frames, RenderSettings().size
    else:
        source = load_scene(args.scene).with_options(
            fps=args.fps, seconds=args.seconds, method=args.method, substeps=args.substeps,
            broadphase=args.broadphase, restitution=args.restitution)
        name, fps, frames, base = source.name, source.fps, source.frames, source.render.size
    suffix = ".png" if args.png is not None else ".mp4"
    out = args.out or Path("renders") / f"{name}{suffix}"
    profile = {} if args.profile else None
    width, height = output_size(base, args.size, args.quality)
    start = time.perf_counter()
    settings = None
    if args.save_trajectory is not None:  # simulate once: save the run, then play it
        source, settings = _saved_trajectory(source, args.save_trajectory), source.render
    path = render(source, out, (width, height), settings=settings, codec=args.codec, quality=args.quality,
                  png_frame=args.png, progress=not args.no_progress, profile=profile)
    seconds = time.perf_counter() - start
    what = f"frame {args.png}" if args.png is not None else f"{frames} frames at {fps:g} fps, {args.codec}"
    print(f"{path}: {what}, {width}x{height}, {seconds:.1f} s")
    if profile:
        print(profile_table(profile))
    return 0


def _saved_trajectory(source, path: Path):
    """Simulate a scene of one world, save its trajectory to path, and return it."""
    from .engine import simulate
    from .io.writers import check_writable
    from .model.scene import Scene
    if not isinstance(source, Scene) or source.world is None:
        raise ValueError("--save-trajectory needs a scene of one world (not panels or chapters)")
    check_writable(Path(path).parent)
    trajectory = simulate(source)
    print(f"{trajectory.save(path)}: trajectory")
    return trajectory


def cmd_bench(args) -> int:
    from .io.writers import check_writable
    check_writable(args.out)
    if args.kind == "broadphase":
        from .analysis.bench.broadphase import run
        if min(args.sizes) < 2 or args.repeats < 1 or not 0 < args.packing < 0.9:
            raise ValueError("sizes must be >= 2, repeats >= 1 and packing in (0, 0.9)")
        figures = run(args.out, sizes=args.sizes, packing=args.packing, repeats=args.repeats,
                      progress=not args.no_progress)
        for n, best in figures["fastest_vs_ckdtree"].items():
            print(f"n={n}: fastest {best['method']}, {best['ratio']:.2f} x cKDTree build + query_pairs; "
                  f"whole discrete step {figures['discrete_vs_pymunk'][n]:.2f} x pymunk's")
        print(f"wrote {figures['csv']} and {figures['png']}")
    elif args.kind == "accuracy":
        from .analysis.bench.accuracy import run
        from .analysis.bench.workloads import WORKLOADS
        _check_positive_seconds(args.seconds)
        unknown = sorted(set(args.workloads or ()) - set(WORKLOADS))
        if unknown or args.repeats < 1:
            raise ValueError(f"unknown workload '{unknown[0]}'; choose from: {', '.join(WORKLOADS)}" if unknown
                             else "repeats must be >= 1")
        figures = run(args.out, workloads=args.workloads, seconds=args.seconds, repeats=args.repeats,
                      progress=not args.no_progress)
        print(format_accuracy_budget(figures["budget"]))
        print(f"wrote {figures['csv']} and {len(figures['png'])} charts")
    elif args.kind == "segments":
        from .analysis.bench.segments import run
        if args.bodies < 2 or args.segments < 1 or args.repeats < 1:
            raise ValueError("bodies must be >= 2, segments >= 1 and repeats >= 1")
        f = run(args.out, n=args.bodies, m=args.segments, repeats=args.repeats)
        print(f"{f['bodies']} bodies: {1e3 * f['seconds_per_frame_without']:.2f} ms a frame; with {f['segments']} "
              f"segments {1e3 * f['seconds_per_frame_with']:.2f} ms ({f['ratio']:.2f} x); wrote {f['json']}")
    elif args.kind == "render":
        from .analysis.bench.render import run
        _check_positive_seconds(args.seconds)
        figures = run(args.out, seconds=args.seconds, memory=not args.no_memory, progress=not args.no_progress)
        print(format_render_figures(figures))
    return 0


def _check_positive_seconds(seconds: float) -> None:
    if not seconds > 0:
        raise ValueError(f"seconds must be a finite number > 0, got {seconds}")


def format_accuracy_budget(budget: dict) -> str:
    lines = [f"ccd / pymunk x1 on {workload}: {ratio:.2f}" for workload, ratio in budget["ccd_over_pymunk_x1"].items()]
    if budget["fast_gas_lossless_pymunk_substeps"] is not None:
        lines.append(f"fast_gas: pymunk first loses no particle at x{budget['fast_gas_lossless_pymunk_substeps']}; "
                     f"ccd / that = {budget['fast_gas_ccd_over_lossless_pymunk']:.2f}")
    return "\n".join(lines)


def format_render_figures(f: dict) -> str:
    split = f["split"]
    lines = [
        f"video job: {f['frames']} frames at {f['size'][0]}x{f['size'][1]}",
        f"render        {f['render_seconds']:7.2f} s  (simulate {split['simulate']:.2f} s, draw {split['draw']:.2f} s, "
        f"encode {split['encode']:.2f} s on its own thread)",
        f"encode only   {f['encode_only_seconds']:7.2f} s  -> render / encode-only = {f['render_over_encode_only']:.2f}",
        f"simulate only {f['simulate_sweep_prune_seconds']:7.2f} s with sweep_prune, "
        f"{f['simulate_brute_seconds']:.2f} s with brute force pair checks",
    ]
    if "peak_memory_mb" in f:
        peaks = ", ".join(f"{k}: {v:.0f} MB" for k, v in f["peak_memory_mb"].items())
        lines.append(f"peak memory rendering particles_250: {peaks}")
    return "\n".join(lines)


def cmd_compare(args) -> int:
    from .analysis.compare import compare, format_table, render_comparison, rows_to_json
    scene = load_scene(args.scene)
    rows = compare(scene, methods=args.methods, seconds=args.seconds, keep_trajectories=args.video is not None)
    print(rows_to_json(rows) if args.json else format_table(rows))
    if args.video is not None:
        print(f"{render_comparison(rows, args.video)}: the compared runs side by side")
    return 0


COMMANDS = {"list": cmd_list, "render": cmd_render, "bench": cmd_bench, "compare": cmd_compare}


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            status = COMMANDS[args.command](args)
        except ValueError as error:
            print(f"collisim: error: {error}", file=sys.stderr)
            status = 2
        except KeyboardInterrupt:
            print("collisim: interrupted; no file written", file=sys.stderr)
            status = 130
        except BrokenPipeError:  # the reader (e.g. `head`) stopped reading: stop quietly
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            status = 0
        for warning in caught:
            print(f"collisim: note: {warning.message}", file=sys.stderr)
    return status
