"""The `collisim` command: list scenes, render them, compare methods, run the benchmarks and sweeps.

Bad input gives one line on stderr and exit status 2; never a traceback, never a partial file.
Ctrl-C, SIGTERM and SIGHUP end a command alike: temporaries removed, one line, status 128 + signal.
"""
from __future__ import annotations

import argparse
import os
import signal
import sys
import threading
import time
import warnings
from contextlib import contextmanager
from pathlib import Path

from . import __version__
from .analysis.sweep.cli import add_sweep_parser, cmd_sweep
from .broadphase import NAMES as BROAD_PHASES
from .engine import METHODS
from .engine.profile import profile_table
from .io.formats import FORMATS
from .model.scenefile import available_scenes, describe_scene_file, load_scene
from .render.video import QUALITIES, THEMES


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
    parser.add_argument("--version", action="version", version=f"collisim {__version__}")
    commands = parser.add_subparsers(dest="command", required=True, parser_class=OneLineParser)
    commands.add_parser("list", help="list the scenes with a one-line description")
    render = commands.add_parser("render", help="render a scene to a video, a PNG sequence or one PNG frame")
    add_render_options(render)
    add_bench_parser(commands)
    add_sweep_parser(commands)
    compare = commands.add_parser("compare", help="run collisim's methods and pymunk on one scene, one table")
    compare.add_argument("scene", help="scene name or path")
    compare.add_argument("--methods", nargs="+", help="labels such as 'discrete x1' 'discrete x8' ccd 'pymunk x1'")
    compare.add_argument("--seconds", type=float, help="simulated duration")
    compare.add_argument("--json", action="store_true", help="print JSON instead of a table")
    compare.add_argument("--video", type=Path, metavar="PATH",
                         help="also render the compared runs side by side, titled, to PATH")
    return parser


def add_render_options(render) -> None:
    render.add_argument("scene", help="scene name (e.g. single_bounce), path to a scene file, or a saved "
                                      "trajectory (.npz)")
    render.add_argument("--out", help="a file (.mp4 .webm .gif .mov), DIR/ for DIR/<scene>.<ext>, or with "
                                      "--format png the sequence's folder (default renders/<scene>/<quality>.<ext>)")
    render.add_argument("--format", choices=tuple(FORMATS), help="mp4 (default), webm, gif, mov, or png (a "
                                                                 "sequence); else the extension of --out")
    render.add_argument("--fps", type=float, help="frame rate of the video (the simulation keeps its own step)")
    render.add_argument("--physics-fps", type=float, metavar="N", help="simulation steps per second")
    render.add_argument("--seconds", type=float, help="duration")
    render.add_argument("--size", type=parse_size, help="frame size WxH (default: the scene's, by quality)")
    render.add_argument("-q", "--quality", choices=tuple(QUALITIES),
                        help="-ql 480p15, -qm 720p30, -qh 1080p60, -qk 2160p60: size, video fps and "
                             "encoder quality (default: the scene's size and fps)")
    render.add_argument("--codec", choices=FORMATS["mp4"].codecs, help="mp4 only: h264 (default) or mp4v")
    render.add_argument("--transparent", action="store_true", help="background alpha 0 (webm, mov, png)")
    render.add_argument("--background", metavar="#RRGGBB", help="background colour")
    render.add_argument("--theme", choices=tuple(THEMES), default="dark", help="colour theme (default dark)")
    render.add_argument("-s", "--last-frame", action="store_true", help="write the last frame as PNG")
    render.add_argument("--png", type=int, metavar="FRAME", help="write frame FRAME as PNG instead of a video")
    render.add_argument("--no-limits", action="store_true",
                        help="allow frames over 7680x4320 and videos over 100000 frames")
    render.add_argument("--method", choices=tuple(METHODS))
    render.add_argument("--substeps", type=int, help="discrete steps per frame")
    render.add_argument("--broadphase", choices=("auto",) + BROAD_PHASES, help="broad phase")
    render.add_argument("--restitution", type=float, help="coefficient of restitution e in [0, 1]")
    render.add_argument("--profile", action="store_true", help="print time per phase at the end")
    render.add_argument("--no-progress", action="store_true", help="no progress bar")
    render.add_argument("--save-trajectory", type=Path, metavar="PATH",
                        help="also write the simulated trajectory to PATH (.npz) (scenes of one world)")


def add_bench_parser(commands) -> None:
    bench = commands.add_parser("bench", help="benchmarks: speed as ratios against references in the same run")
    kinds = bench.add_subparsers(dest="kind", required=True, parser_class=OneLineParser)
    broad = kinds.add_parser("broadphase", help="time per frame of each broad phase against n, with scipy "
                                                "cKDTree, plain pymunk and a minimal compiled step as references")
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
    maps = kinds.add_parser("maps", help="a collision map's accuracy against its resolution (0.5 to 16 cells "
                                         "per particle radius) against the exact level")
    maps.add_argument("--cells", type=float, nargs="+", default=[0.5, 1, 2, 4, 8, 16],
                      help="map cells per particle radius")
    maps.add_argument("--seconds", type=float, default=1.0, help="simulated time per measurement")
    rays = kinds.add_parser("rays", help="ray queries into the 250-particle gas: ns per ray for each broad phase "
                                         "against pymunk's segment_query_first, in the same run")
    rays.add_argument("--rays", type=int, default=100_000, help="rays cast per measurement")
    rays.add_argument("--repeats", type=int, default=3)
    polygons = kinds.add_parser("polygons", help="the polygons scene: collisim's discrete step against plain "
                                                 "pymunk's on the same world, per phase, as ratios")
    polygons.add_argument("--seconds", type=float, default=8.0, help="simulated seconds per repeat")
    polygons.add_argument("--repeats", type=int, default=3)
    for parser in (broad, render, accuracy, segments, maps, rays, polygons):
        parser.add_argument("--out", type=Path, default=Path("renders/bench"), help="folder for CSV and PNG")
        parser.add_argument("--no-progress", action="store_true")


def cmd_list(args) -> int:
    scenes = available_scenes()
    width = max((len(name) for name in scenes), default=0)
    for name, path in scenes.items():
        print(f"{name:<{width}}  {describe_scene_file(path)}")
    return 0


def note(message: str) -> None:
    print(f"collisim: note: {message}", file=sys.stderr, flush=True)


PHYSICS_FLAGS = {"method": "--method", "substeps": "--substeps", "broadphase": "--broadphase",
                 "restitution": "--restitution", "physics_fps": "--physics-fps"}


def render_source(args):
    """(source, name, fps): the scene with the command line's physics applied, or the saved
    trajectory, and its own frame rate before --physics-fps; a note names the physics flags a
    source ignores."""
    from .model.trajectory import load_trajectory
    given = [flag for key, flag in PHYSICS_FLAGS.items() if getattr(args, key) is not None]
    if str(args.scene).endswith(".npz"):
        source = load_trajectory(args.scene)
        if given:
            note(f"a saved trajectory plays as it was simulated; ignoring {', '.join(given)}")
        return source, Path(args.scene).stem, source.fps
    scene = load_scene(args.scene)
    if scene.world is None:  # panels or chapters: their own physics is what they show
        if given:
            kind = "panels" if scene.panels else "chapters"
            note(f"{scene.name} is made of {kind} that keep their own physics (they exist to compare "
                 f"settings); ignoring {', '.join(given)}")
        return scene.with_options(seconds=args.seconds), scene.name, scene.fps
    return scene.with_options(fps=args.physics_fps, seconds=args.seconds, method=args.method,
                              substeps=args.substeps, broadphase=args.broadphase,
                              restitution=args.restitution), scene.name, scene.fps


def default_out(job, args) -> str:
    """renders/<scene>/<quality>.<ext>: the quality as manim names it (480p15, 720p30, 1080p60,
    2160p60, or height p fps), or WxH for --size; a PNG sequence is the folder without extension."""
    if args.last_frame or args.png is not None:
        extension = ".png"
    else:
        extension = FORMATS[args.format or "mp4"].extension
    return str(Path("renders") / job.name / f"{job.label}{extension}")


def cmd_render(args) -> int:
    from .model.scene import RenderSettings, Scene
    from .pipeline import output_for, plan, render
    from .render.video import Progress

    start = time.perf_counter()
    source, name, own_fps = render_source(args)
    settings = None if isinstance(source, Scene) else RenderSettings()
    fps = args.fps
    if fps is None and args.quality is None:
        fps = own_fps   # the scene's video rate, even when --physics-fps changed its step
    job = plan(source, args.size, fps=fps, quality=args.quality, settings=settings, name=name,
               limits=not args.no_limits)
    out = output_for(job, args.out if args.out is not None else default_out(job, args), format=args.format,
                     codec=args.codec, transparent=args.transparent, background=args.background, theme=args.theme,
                     png_frame=args.png, last_frame=args.last_frame)
    profile = {} if args.profile else None
    with Progress(bar=not args.no_progress) as progress:
        if args.save_trajectory is not None:  # simulate once: save the run, then play it
            trajectory = _saved_trajectory(source, args.save_trajectory)
            job = plan(trajectory, job.size, fps=job.fps, settings=source.render, name=name, limits=False)
        path = render(job, out.path, format=out.format, codec=out.codec, transparent=out.transparent,
                      background=args.background, theme=args.theme, png_frame=out.frame, quality=args.quality,
                      progress=progress,
                      profile=profile)
    seconds = time.perf_counter() - start
    if out.frame is not None:
        what = f"frame {out.frame}"
    elif out.format == "png":
        what = f"{job.frames} PNG frames at {job.fps:g} fps"
    else:
        what = f"{job.frames} frames at {job.fps:g} fps, {out.format} ({out.codec})"
    compiling = f" ({progress.compile_seconds:.1f} s compiling)" if progress.compiled else ""
    print(f"{path}: {what}, {job.size[0]}x{job.size[1]}, {seconds:.1f} s{compiling}")
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
                  f"collisim discrete step / pymunk step {figures['discrete_vs_pymunk'][n]:.2f}, "
                  f"/ reference step {figures['discrete_vs_reference'][n]:.2f}")
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
    elif args.kind == "maps":
        from .analysis.bench.maps import HEADER, run
        _check_positive_seconds(args.seconds)
        if not all(0 < k <= 64 for k in args.cells):
            raise ValueError("cells per radius must be in (0, 64]")
        if not args.no_progress:
            print(HEADER)
        figures = run(args.out, cells=args.cells, seconds=args.seconds, progress=not args.no_progress)
        print(f"wrote {figures['csv']} and {figures['png']}")
    elif args.kind == "rays":
        from .analysis.bench.rays import bench_rays, format_rays
        if args.rays < 1 or args.repeats < 1:
            raise ValueError("rays and repeats must be >= 1")
        print(format_rays(bench_rays(count=args.rays, repeats=args.repeats)))
    elif args.kind == "polygons":
        from .analysis.bench.polygons import format_rows, load_world, run
        world, fps = load_world()
        rows, profile = run(args.seconds, args.repeats, world, fps)
        print(format_rows(rows, world.n, profile))
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
    """The budget lines; every pymunk figure is plain pymunk (defaults, no callbacks), except the
    mirror's own line."""
    lines = [f"ccd / pymunk x1 on {workload}: {ratio:.2f}" for workload, ratio in budget["ccd_over_pymunk_x1"].items()]
    if budget["fast_gas_lossless_pymunk_substeps"] is not None:
        lines.append(f"fast_gas: pymunk first loses no particle at x{budget['fast_gas_lossless_pymunk_substeps']}; "
                     f"ccd / that = {budget['fast_gas_ccd_over_lossless_pymunk']:.2f}")
    elif "fast_gas" in budget.get("lossless_pymunk_substeps", {}):
        lines.append("fast_gas: pymunk loses a particle at every substep count tried")
    for workload, ratio in budget.get("mirror_over_pymunk_x1", {}).items():
        lines.append(f"pymunk mirror (callbacks) x1 / pymunk x1 on {workload}: {ratio:.2f} (the comparison "
                     f"mirror, not a baseline)")
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


COMMANDS = {"list": cmd_list, "render": cmd_render, "bench": cmd_bench, "compare": cmd_compare, "sweep": cmd_sweep}


class Interrupted(KeyboardInterrupt):
    """A signal that ends the command like Ctrl-C: every output's temporary is removed on the way
    out (a KeyboardInterrupt, so nothing that catches Exception swallows it)."""

    def __init__(self, signum: int):
        super().__init__(signal.Signals(signum).name)
        self.signum = signum


STOP_SIGNALS = tuple(getattr(signal, name) for name in ("SIGINT", "SIGTERM", "SIGHUP") if hasattr(signal, name))


@contextmanager
def signals_interrupt():
    """While open, SIGINT, SIGTERM and SIGHUP raise Interrupted in the main thread; once one has,
    further ones are ignored so that the clean-up runs to its end."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    fired = []

    def stop(signum, frame):
        if not fired:
            fired.append(signum)
            raise Interrupted(signum)

    previous = {number: signal.signal(number, stop) for number in STOP_SIGNALS}
    try:
        yield
    finally:
        for number, handler in previous.items():
            signal.signal(number, handler)


def say(line: str) -> None:
    """A last line on stderr, which may be gone (a closed terminal after SIGHUP)."""
    try:
        print(line, file=sys.stderr, flush=True)
    except (OSError, ValueError):
        pass


def show_note(message, category, filename, lineno, file=None, line=None) -> None:
    """A warning, as one line on stderr when it happens (before the bar, or clearing it)."""
    say(f"collisim: note: {message}")


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    with warnings.catch_warnings(), signals_interrupt():
        warnings.simplefilter("always")
        warnings.showwarning = show_note
        try:
            status = COMMANDS[args.command](args)
        except ValueError as error:
            say(f"collisim: error: {error}")
            status = 2
        except KeyboardInterrupt as interrupt:
            signum = getattr(interrupt, "signum", signal.SIGINT)
            say(f"collisim: interrupted ({signal.Signals(signum).name}); no file written")
            status = 128 + signum
        except BrokenPipeError:  # the reader (e.g. `head`) stopped reading: stop quietly
            os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
            status = 0
    return status
