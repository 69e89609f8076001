"""`collisim bench`: each benchmark's options, its run and the summary it prints.

Speed is always a ratio against references measured in the same run (see the modules beside this one).
"""
from __future__ import annotations

from pathlib import Path


def add_bench_parser(commands) -> None:
    """Add the `bench` subcommand and its kinds to collisim's subparsers."""
    bench = commands.add_parser("bench", help="benchmarks: speed as ratios against references in the same run")
    kinds = bench.add_subparsers(dest="kind", required=True, parser_class=type(bench))  # one-line errors
    broad = kinds.add_parser("broadphase", help="time per frame of each broad phase against n, with scipy "
                                                "cKDTree, plain pymunk and a minimal compiled step as references")
    broad.add_argument("--sizes", type=int, nargs="+", default=[100, 300, 1000, 3000, 10000, 30000, 100000])
    broad.add_argument("--repeats", type=int, default=3)
    broad.add_argument("--packing", type=float, nargs="+", default=[0.1, 0.3, 0.5],
                       help="shares of the box the circles cover, one panel each")
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
    polygons = kinds.add_parser("polygons", help="the polygons scene or a pyramid of boxes: collisim's discrete "
                                                 "step against plain pymunk's (without and with sleeping) and "
                                                 "Box2D 2.3's on the same world, per phase, as ratios")
    polygons.add_argument("--seconds", type=float, default=8.0, help="simulated seconds per repeat")
    polygons.add_argument("--repeats", type=int, default=3)
    polygons.add_argument("--scene", default="polygons", help="pyramid40 (820 boxes), pyramids10 (ten of 55) or "
                                                              "another scene of one world (bounding_volumes): "
                                                              "timed in its first second and whole")
    ccd = kinds.add_parser("ccd", help="the event-driven ccd method's collisions per second (cell crossings "
                                       "apart), and its cost against "
                                       "plain pymunk at its first loss-free substep count, on the three gases")
    ccd.add_argument("--workloads", nargs="+", default=["slow_gas", "dense_gas", "fast_gas"],
                     help="slow_gas dense_gas fast_gas")
    ccd.add_argument("--sizes", type=int, nargs="+", default=[1000, 10000])
    ccd.add_argument("--seconds", type=float, default=1.0, help="simulated seconds per run")
    ccd.add_argument("--repeats", type=int, default=3)
    for parser in (broad, render, accuracy, segments, maps, rays, polygons, ccd):
        parser.add_argument("--out", type=Path, default=Path("renders/bench"), help="folder for CSV and PNG")
        parser.add_argument("--no-progress", action="store_true")


def cmd_bench(args) -> int:
    """Run the chosen benchmark and print its summary; bad options are one ValueError line."""
    from ...io.writers import check_writable
    check_writable(args.out)
    if args.kind == "broadphase":
        from .broadphase import run
        if min(args.sizes) < 2 or args.repeats < 1 or not all(0 < p <= 0.5 for p in args.packing):
            raise ValueError("sizes must be >= 2, repeats >= 1 and packings in (0, 0.5]")
        figures = run(args.out, sizes=args.sizes, packings=args.packing, repeats=args.repeats,
                      progress=not args.no_progress)
        ranges = {(row["packing"], row["n"], row["method"]):
                  (f"{row['step_over_pymunk']:.2f} ({row['over_pymunk_range']})",
                   f"{row['step_over_minimal']:.2f} ({row['over_minimal_range']})")
                  for row in figures["rows"] if row["method"] in ("discrete_step", "simulate")}
        print(f"collisim / a reference: the medians' ratio (the range of one round's ratio over {args.repeats} rounds)")
        for (packing, n), best in figures["fastest_vs_ckdtree"].items():
            engine, simulate = ranges[(packing, n, "discrete_step")], ranges[(packing, n, "simulate")]
            print(f"packing {packing:g} n={n}: fastest broad phase {best['method']}, {best['ratio']:.2f} x cKDTree; "
                  f"engine / pymunk {engine[0]}, / minimal step {engine[1]}; "
                  f"simulate() / pymunk {simulate[0]}, / minimal step {simulate[1]}")
        print(f"wrote {figures['csv']} and {figures['png']}")
    elif args.kind == "accuracy":
        from .accuracy import run
        from .workloads import WORKLOADS
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
        from .segments import run
        if args.bodies < 2 or args.segments < 1 or args.repeats < 1:
            raise ValueError("bodies must be >= 2, segments >= 1 and repeats >= 1")
        f = run(args.out, n=args.bodies, m=args.segments, repeats=args.repeats)
        print(f"{f['bodies']} bodies: {1e3 * f['seconds_per_frame_without']:.2f} ms a frame; with {f['segments']} "
              f"segments {1e3 * f['seconds_per_frame_with']:.2f} ms ({f['ratio']:.2f} x); wrote {f['json']}")
    elif args.kind == "maps":
        from .maps import HEADER, run
        _check_positive_seconds(args.seconds)
        if not all(0 < k <= 64 for k in args.cells):
            raise ValueError("cells per radius must be in (0, 64]")
        if not args.no_progress:
            print(HEADER)
        figures = run(args.out, cells=args.cells, seconds=args.seconds, progress=not args.no_progress)
        print(f"wrote {figures['csv']} and {figures['png']}")
    elif args.kind == "rays":
        from .rays import bench_rays, format_rays
        if args.rays < 1 or args.repeats < 1:
            raise ValueError("rays and repeats must be >= 1")
        print(format_rays(bench_rays(count=args.rays, repeats=args.repeats)))
    elif args.kind == "polygons":
        from .polygons import asleep_cost, format_asleep, format_rows, load_world, run
        world, fps = load_world(args.scene)
        rows, extra = run(args.seconds, args.repeats, world, fps, falling=args.scene == "polygons")
        print(format_rows(rows, extra, args.scene))
        print(format_asleep(asleep_cost(world, fps, args.repeats)))
    elif args.kind == "ccd":
        from .ccd import format_table, run
        _check_positive_seconds(args.seconds)
        figures = run(args.out, workloads=args.workloads, sizes=args.sizes, seconds=args.seconds,
                      repeats=args.repeats, progress=not args.no_progress)
        print(format_table(figures["rows"]))
        print(f"wrote {figures['csv']}")
    elif args.kind == "render":
        from .render import run
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
        f"encode only   {f['encode_only_seconds']:7.2f} s  -> render / encode-only = "
        f"{f['render_over_encode_only']:.2f}",
        f"simulate only {f['simulate_sweep_prune_seconds']:7.2f} s with sweep_prune, "
        f"{f['simulate_brute_seconds']:.2f} s with brute force pair checks",
    ]
    if "stills" in f:
        from .render import format_stills
        lines.append(format_stills(f["stills"]))
    if "peak_memory_mb" in f:
        peaks = ", ".join(f"{k}: {v:.0f} MB" for k, v in f["peak_memory_mb"].items())
        lines.append(f"peak memory rendering particles_250: {peaks}")
    return "\n".join(lines)
