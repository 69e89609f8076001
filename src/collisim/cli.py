"""The `collisim` command: list scenes, render them, compare methods, run the benchmarks and sweeps.

Bad input gives one line on stderr and exit status 2; never a traceback, never a partial file.
Ctrl-C, SIGTERM and SIGHUP end a command alike: temporaries removed, one line, status 128 + signal.
"""
from __future__ import annotations

import argparse
import gc
import os
import re
import signal
import sys
import time
import traceback
import warnings
from pathlib import Path

from . import __version__, warm
from .analysis.bench.cli import add_bench_parser, cmd_bench
from .analysis.sweep.cli import add_sweep_parser, cmd_sweep
from .broadphase import NAMES as BROAD_PHASES
from .engine import METHODS, ahead
from .engine.profile import profile_table
from .interrupts import signals_interrupt
from .io.formats import BY_EXTENSION, FORMATS
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


def parse_resolution(text: str) -> tuple:
    """manim's -r: "W,H" (manim also splits on ';' and '-'); a single number is refused, as
    manim refuses it."""
    try:
        width, height = (int(v) for v in re.split(r"[;,\-]", text))
    except ValueError:
        raise argparse.ArgumentTypeError(f"resolution must look like 1280,720 (width,height), got '{text}'") from None
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
                                      "--format png the sequence's folder (default renders/<scene>/<quality>.<ext>, "
                                      "with the physics flags that change the scene: 720p30_ccd.mp4)")
    render.add_argument("-o", "--output_file", metavar="NAME",
                        help="as manim: the file's name in renders/<scene>/ (the format's extension added when "
                             "missing)")
    render.add_argument("--format", choices=tuple(FORMATS), help="mp4 (default), webm, gif, mov, or png (a "
                                                                 "sequence); else the extension of --out")
    render.add_argument("--fps", type=float, help="frame rate of the video (the simulation keeps its own step)")
    render.add_argument("--physics-fps", type=float, metavar="N", help="simulation steps per second")
    render.add_argument("--seconds", type=float, help="duration")
    render.add_argument("--size", type=parse_size, help="frame size WxH (default: the scene's, by quality)")
    render.add_argument("-r", "--resolution", type=parse_resolution, dest="size", metavar="W,H",
                        help="as manim: the frame size as width,height (the same as --size WxH)")
    render.add_argument("-q", "--quality", choices=tuple(QUALITIES),
                        help="-ql 480p15, -qm 720p30, -qh 1080p60, -qk 2160p60: size, video fps and "
                             "encoder quality (default: the scene's size and fps); a scene whose lesson needs a "
                             "higher rate keeps it (RenderSettings.min_fps) and says so")
    render.add_argument("--codec", choices=FORMATS["mp4"].codecs, help="mp4 only: h264 (default) or mp4v")
    render.add_argument("-t", "--transparent", action="store_true", help="background alpha 0 (webm, mov, png)")
    render.add_argument("--background", metavar="#RRGGBB", help="background colour")
    render.add_argument("--theme", choices=tuple(THEMES),
                        help="colour theme (default: the one whose text reads on --background, else dark)")
    render.add_argument("-s", "--last-frame", action="store_true", help="write the last frame as PNG")
    render.add_argument("--png", type=int, metavar="FRAME", help="write frame FRAME as PNG instead of a video")
    render.add_argument("--no-limits", action="store_true",
                        help="allow frames over 7680x4320, videos over 100000 frames and "
                             "simulations over 10000000 steps")
    render.add_argument("--method", choices=tuple(METHODS))
    render.add_argument("--substeps", type=int, help="discrete steps per frame")
    render.add_argument("--broadphase", choices=("auto",) + BROAD_PHASES, help="broad phase")
    render.add_argument("--restitution", type=float, help="coefficient of restitution e in [0, 1]")
    render.add_argument("--profile", action="store_true", help="print time per phase at the end")
    render.add_argument("--no-progress", action="store_true", help="no progress bar")
    render.add_argument("--save-trajectory", type=Path, metavar="PATH",
                        help="also write the simulated trajectory to PATH (.npz) (scenes of one world)")


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
    """(source, name, fps, variant): the scene with the command line's physics applied, or the
    saved trajectory, its own frame rate before --physics-fps, and what in its physics the flags
    changed, for the default file name (physics_variant); a note names the physics flags a
    source ignores."""
    from .model.trajectory import load_trajectory
    given = [flag for key, flag in PHYSICS_FLAGS.items() if getattr(args, key) is not None]
    if str(args.scene).endswith(".npz"):
        source = load_trajectory(args.scene)
        if args.seconds is not None:   # it plays whole, as long as it was simulated
            given.append("--seconds")
        if given:
            note(f"a saved trajectory plays as it was simulated; ignoring {', '.join(given)}")
        return source, Path(args.scene).stem, source.fps, ""
    scene = load_scene(args.scene)
    if scene.world is None:  # panels or chapters: their own physics is what they show
        if given:
            kind = "panels" if scene.panels else "chapters"
            note(f"{scene.name} is made of {kind} that keep their own physics (they exist to compare "
                 f"settings); ignoring {', '.join(given)}")
        return scene.with_options(seconds=args.seconds), scene.name, scene.fps, ""
    return scene.with_options(fps=args.physics_fps, seconds=args.seconds, method=args.method,
                              substeps=args.substeps, broadphase=args.broadphase,
                              restitution=args.restitution), scene.name, scene.fps, physics_variant(scene, args)


def physics_variant(scene, args) -> str:
    """The physics flags that change a scene of one world, as the default file name's suffix
    (`_ccd`, `_x8`, `_grid`, `_physics30`, `_e0p9`, in that order), so renders of different
    physics do not overwrite each other; '' when none does. A number's point is written p (a
    PNG sequence's folder has no extension). --seconds only cuts the same run: no suffix."""
    def number(value) -> str:
        return f"{value:g}".replace(".", "p")
    changes = [(args.method, scene.method, str), (args.substeps, scene.substeps, lambda k: f"x{k}"),
               (args.broadphase, scene.broadphase, str), (args.physics_fps, scene.fps, lambda f: f"physics{number(f)}"),
               (args.restitution, scene.world.restitution, lambda e: f"e{number(e)}")]
    return "".join(f"_{spell(given)}" for given, own, spell in changes if given is not None and given != own)


def default_out(job, args, variant: str = "") -> str:
    """renders/<scene>/<quality><variant>.<ext>: the quality as manim names it (480p15, 720p30,
    1080p60, 2160p60, or height p fps), or WxH for --size, then what the physics flags changed
    (physics_variant); a PNG sequence is the folder without extension. With -o NAME, as manim:
    renders/<scene>/NAME, its extension added when missing (a .mp4 .webm .gif .mov one names
    the format, as --out's does)."""
    if args.last_frame or args.png is not None:
        extension = ".png"
    else:
        extension = FORMATS[args.format or "mp4"].extension
    if args.output_file is None:
        return str(Path("renders") / job.name / f"{job.label}{variant}{extension}")
    name = args.output_file
    if not name or name.endswith(("/", "\\")) or Path(name).is_absolute():
        raise ValueError(f"-o takes a file name, which goes into renders/{job.name}/, got '{name}' (--out takes "
                         f"a path)")
    own = Path(name).suffix.lower()
    if extension and own != extension and (extension == ".png" or own not in BY_EXTENSION):
        name += extension
    return str(Path("renders") / job.name / name)


def cmd_render(args) -> int:
    from .model.scene import RenderSettings, Scene

    start = time.perf_counter()
    if args.out is not None and args.output_file is not None:
        raise ValueError("choose one output: --out PATH, or -o NAME (a name in renders/<scene>/), not both")
    source, name, own_fps, variant = render_source(args)
    settings = None if isinstance(source, Scene) else RenderSettings()
    profile = {} if args.profile else None
    helper = warm.start(source) if isinstance(source, Scene) else None   # a first run: a second process compiles
    try:
        job, out, path, progress = _render(args, source, name, own_fps, variant, settings, profile)
    finally:
        warm.stop(helper)
    seconds = time.perf_counter() - start
    if out.frame is not None:
        what = f"frame {out.frame}"
    elif out.format == "png":
        what = f"{job.frames} PNG frames at {job.fps:g} fps"
    else:
        what = f"{job.frames} frames at {job.fps:g} fps, {out.format} ({out.codec})"
    compiling = f" ({progress.compile_seconds:.1f} s compiling)" if progress.compiled else ""
    print(f"{path}: {what}, {job.size[0]}x{job.size[1]}, rendered in {seconds:.1f} s{compiling}")
    if profile:
        print(profile_table(profile))
    return 0


def _render(args, source, name, own_fps, variant, settings, profile):
    """Plan the render and play it under the progress bar: (job, output, the file written, the
    Progress)."""
    from .pipeline import output_for, plan, render
    from .render.video import Progress
    fps = args.fps
    if fps is None and args.quality is None:
        fps = own_fps   # the scene's video rate, even when --physics-fps changed its step
    job = plan(source, args.size, fps=fps, quality=args.quality, settings=settings, name=name,
               limits=not args.no_limits)
    out = output_for(job, args.out if args.out is not None else default_out(job, args, variant), format=args.format,
                     codec=args.codec, transparent=args.transparent, background=args.background, theme=args.theme,
                     png_frame=args.png, last_frame=args.last_frame)
    with Progress(bar=not args.no_progress) as progress:
        if args.save_trajectory is not None:  # simulate once: save the run, then play it
            trajectory = _saved_trajectory(source, args.save_trajectory)
            job = plan(trajectory, job.size, fps=job.fps, settings=source.render, name=name, limits=False)
        path = render(job, out.path, format=out.format, codec=out.codec, transparent=out.transparent,
                      background=args.background, theme=args.theme, png_frame=out.frame, quality=args.quality,
                      progress=progress, profile=profile)
    return job, out, path, progress


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


def cmd_compare(args) -> int:
    from .analysis.compare import compare, format_table, render_comparison, rows_to_json
    scene = load_scene(args.scene)
    rows = compare(scene, methods=args.methods, seconds=args.seconds, keep_trajectories=args.video is not None)
    print(rows_to_json(rows) if args.json else format_table(rows))
    if args.video is not None:
        print(f"{render_comparison(rows, args.video)}: the compared runs side by side")
    return 0


COMMANDS = {"list": cmd_list, "render": cmd_render, "bench": cmd_bench, "compare": cmd_compare, "sweep": cmd_sweep}


def say(line: str) -> None:
    """A last line on stderr, which may be gone (a closed terminal after SIGHUP)."""
    try:
        print(line, file=sys.stderr, flush=True)
    except (OSError, ValueError):
        pass


def show_note(message, category, filename, lineno, file=None, line=None) -> None:
    """A warning, as one line on stderr when it happens (before the bar, or clearing it)."""
    say(f"collisim: note: {message}")


def scene_code(error: BaseException) -> str | None:
    """Where in a scene's own code an error was raised ("file, line N, in name": the innermost
    frame of a file outside collisim and the Python installation, such as an overlay or a
    caption function), or None if it came from nowhere such."""
    package = Path(__file__).resolve().parent
    installation = [Path(p).resolve() for p in {sys.prefix, sys.base_prefix, sys.exec_prefix}]
    found = None
    for frame, line in traceback.walk_tb(error.__traceback__):
        path = Path(frame.f_code.co_filename)
        if not path.is_file():
            continue   # <frozen ...>, <string>
        path = path.resolve()
        if not path.is_relative_to(package) and not any(path.is_relative_to(p) for p in installation):
            found = f"{path.name}, line {line}, in {frame.f_code.co_name}"
    return found


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    with warnings.catch_warnings(), signals_interrupt() as received:
        warnings.simplefilter("always")
        warnings.showwarning = show_note
        try:
            status = COMMANDS[args.command](args)
        except KeyboardInterrupt as interrupt:
            status = _interrupted(getattr(interrupt, "signum", signal.SIGINT))
        except Exception as error:   # noqa: BLE001 - said in one line, or a defect of collisim's
            # after a signal, any error is the interrupt's, which C code it ran through may have
            # put in its own words (interrupts.signals_interrupt)
            status = _interrupted(received[0]) if received else _failed(error)
    return status


def _failed(error: Exception) -> int:
    """The exit status of a command that raised `error`, having said why in one line; or the
    error raised again, a defect of collisim's, whose traceback is the report."""
    if isinstance(error, ValueError):
        say(f"collisim: error: {error}")
        return 2
    if isinstance(error, BrokenPipeError):  # the reader (e.g. `head`) stopped reading: stop quietly
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
    where = scene_code(error)
    if where is None:
        raise error
    say(f"collisim: error: the scene's code raised {type(error).__name__}: {error} ({where})")
    return 2


def _interrupted(signum: int) -> int:
    """Say that a signal ended the command (every output's temporary is removed by then); its
    exit status."""
    say(f"collisim: interrupted ({signal.Signals(signum).name}); no file written")
    return 128 + signum


def run(argv=None) -> None:
    """The `collisim` command (and `python -m collisim`): main in a process of its own, which
    it ends with main's exit status.

    Why the collector is frozen: what importing made (numba's registries, a dispatcher per
    kernel) lives as long as the process, and at exit Python's last collection walks every
    object there is, a hundred thousand and more once the kernels are loaded: 0.15-0.2 s of a
    warm first frame (particles_250: 1.10-1.15 s, then 0.89-0.95 s), for memory the process is
    about to hand back whole. Frozen objects
    are never collected; frozen after the imports, they are skipped by the collections during
    the command too (what the command makes is still collected), and frozen again at the end,
    everything is skipped. main alone (the API, the tests) changes nothing of the caller's."""
    gc.freeze()
    status = main(argv)
    gc.freeze()
    if status > 128:
        # a signal ended the command (main said so, last): an object the signal cut short in its
        # making (pyparsing's, building mathtext's grammar) may fail again in its finalizer as
        # Python frees it at exit, which printed a traceback under the last line; it is the
        # interrupt's, already said
        sys.unraisablehook = lambda unraisable: None
    if ahead.computing():
        # a signal or an error ended the command while the engine's thread was in a block, maybe
        # compiling it: everything the command wrote is cleaned up by now, and Python's teardown
        # (or waiting for the compile, as the API does at exit) would free numba's and LLVM's
        # objects under that thread, which made LLVM abort the process. So it ends here.
        sys.stdout.flush()
        sys.stderr.flush()
        os._exit(status)
    sys.exit(status)
