"""The first run on a fresh install: time to a scene's first frame with an empty compile cache
(cold), then again with the cache that run left (warm), and what numba compiled on the way.

Each run is `collisim render SCENE --png 1` in a fresh Python process whose NUMBA_CACHE_DIR
and COLLISIM_CACHE_DIR (typeset text, render/textcache.py) are a new temporary folder, so the
repository's and the user's caches are never read nor deleted. The process ends as the
collisim command does (cli.run: the collector frozen after the imports and at the end) and
keeps the modules' bytecode as a user's Python does (PYTHONDONTWRITEBYTECODE is dropped). The
cold process listens to numba's "numba:compile" events (fired only when a kernel is compiled,
never when one is loaded from the cache) and reports, per function, how many times it compiled
and the seconds it spent compiling itself (a compile's own time: less the kernels it compiled
on the way, which are timed as theirs), and both runs time numba's cache (entries loaded,
seconds loading and saving). Wall seconds are the process's as the parent sees it; on a shared
machine its CPU seconds are the steadier figure.

    python benchmarks/first_run.py particles_250 --method discrete ccd --top 15
"""
from __future__ import annotations

import argparse
import gc
import json
import os
import subprocess
import sys
import tempfile
import time

from numba.core import event as numba_event


class CompileRecorder(numba_event.Listener):
    """Per compiled function: compiles, own seconds, and the signatures compiled."""

    def __init__(self):
        self.functions, self._stack = {}, []

    def on_start(self, event):
        self._stack.append([time.perf_counter(), 0.0])

    def on_end(self, event):
        start, nested = self._stack.pop()
        seconds = time.perf_counter() - start
        if self._stack:
            self._stack[-1][1] += seconds
        data = event.data
        function = data["dispatcher"].py_func
        name = f"{function.__module__}.{function.__qualname__}"
        entry = self.functions.setdefault(name, {"compiles": 0, "seconds": 0.0, "signatures": []})
        entry["compiles"] += 1
        entry["seconds"] += seconds - nested
        entry["signatures"].append(", ".join(str(a) for a in data["args"]))


class CacheTimer:
    """Time spent in numba's cache: loading entries (the warm run's cost besides importing and
    running) and saving them (part of the cold run's compiling)."""

    def __init__(self):
        from numba.core import caching
        self.loaded = self.load_seconds = self.save_seconds = 0
        load, save = caching.Cache.load_overload, caching.Cache.save_overload

        def timed_load(cache, *args):
            start = time.perf_counter()
            data = load(cache, *args)
            self.load_seconds += time.perf_counter() - start
            self.loaded += data is not None
            return data

        def timed_save(cache, *args):
            start = time.perf_counter()
            save(cache, *args)
            self.save_seconds += time.perf_counter() - start

        caching.Cache.load_overload, caching.Cache.save_overload = timed_load, timed_save


def _child(scene: str, method: str | None) -> dict:
    """Render frame 1 of scene in this process; what it took and what compiled (run in a fresh process)."""
    start = time.perf_counter()
    recorder, cache = CompileRecorder(), CacheTimer()
    numba_event.register("numba:compile", recorder)
    from collisim.cli import main
    imported = time.perf_counter()
    gc.freeze()   # as the collisim command does (cli.run), here and once the report is out
    with tempfile.TemporaryDirectory() as out:
        args = ["render", scene, "--png", "1", "--out", os.path.join(out, "frame.png"), "--no-progress"]
        status = main(args + (["--method", method] if method else []))
    done = time.perf_counter()
    return {"status": status, "import_seconds": imported - start, "seconds": done - start,
            "cpu_seconds": time.process_time(),   # the whole process's, interpreter start included
            "cache_loads": cache.loaded,
            "cache_load_seconds": cache.load_seconds, "cache_save_seconds": cache.save_seconds,
            "compile_seconds": sum(f["seconds"] for f in recorder.functions.values()),
            "compiles": sum(f["compiles"] for f in recorder.functions.values()), "functions": recorder.functions}


def measure(scene: str, method: str | None = None, warm_repeats: int = 1) -> dict:
    """Cold then warm first frame of scene in fresh processes sharing one new cache folder:
    {"cold": child report, "warm": [child reports], "wall": {cold, warm: process seconds}}."""
    with tempfile.TemporaryDirectory(prefix="collisim-numba-") as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache, COLLISIM_CACHE_DIR=cache)   # typeset text too
        # a user's Python keeps the modules' bytecode: without it every run compiles collisim's
        # sources again (0.13 s of a warm run)
        env.pop("PYTHONDONTWRITEBYTECODE", None)
        runs, walls = [], []
        for _ in range(1 + warm_repeats):
            command = [sys.executable, os.path.abspath(__file__), "--child", scene]
            started = time.perf_counter()
            done = subprocess.run(command + (["--method", method] if method else []), env=env,
                                  capture_output=True, text=True)
            walls.append(time.perf_counter() - started)
            if done.returncode != 0:
                last = (done.stderr.strip().splitlines() or ["no output"])[-1]
                raise RuntimeError(f"{scene} ({method or 'its own method'}) failed: {last}")
            runs.append(json.loads(done.stdout.strip().splitlines()[-1]))
    return {"scene": scene, "method": method, "cold": runs[0], "warm": runs[1:],
            "wall": {"cold": walls[0], "warm": walls[1:]}}


def format_functions(report: dict, top: int = 15) -> str:
    """The cold run's compiled functions, most own compile time first, and every function compiled
    more than once."""
    functions = report["cold"]["functions"]
    ranked = sorted(functions.items(), key=lambda item: -item[1]["seconds"])
    lines = [f"{'own s':>7} {'n':>3}  function"]
    lines += [f"{f['seconds']:7.2f} {f['compiles']:3d}  {name}" for name, f in ranked[:top]]
    repeated = [(name, f) for name, f in ranked if f["compiles"] > 1]
    if repeated:
        lines.append("compiled more than once:")
        lines += [f"{f['seconds']:7.2f} {f['compiles']:3d}  {name}" for name, f in repeated]
    return "\n".join(lines)


def format_row(report: dict) -> str:
    cold, warm = report["cold"], report["warm"]
    row = (f"{report['scene']:<15} {report['method'] or '(own)':<9} cold {report['wall']['cold']:6.1f} s "
           f"(cpu {cold['cpu_seconds']:.1f} s; {cold['compiles']} compiles, {cold['compile_seconds']:.1f} s "
           f"compiling, {cold['cache_save_seconds']:.1f} s of it saving)")
    if not warm:   # --warm 0: the cold run alone
        return row
    warm_text = ", ".join(f"{w:.2f}" for w in report["wall"]["warm"])
    warm_cpu = ", ".join(f"{w['cpu_seconds']:.2f}" for w in warm)
    return (f"{row}  warm {warm_text} s (cpu {warm_cpu} s; "
            f"{max(w['compiles'] for w in warm)} compiles, {warm[0]['cache_loads']} cache loads "
            f"{warm[0]['cache_load_seconds']:.2f} s, import {min(w['import_seconds'] for w in warm):.2f} s)")


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("scenes", nargs="+")
    parser.add_argument("--method", nargs="*", default=[None], help="discrete, ccd (default: the scene's own)")
    parser.add_argument("--warm", type=int, default=2, help="warm runs after the cold one")
    parser.add_argument("--top", type=int, default=0, help="list the cold run's N costliest compiles")
    parser.add_argument("--json", help="also write every report to this file")
    parser.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.warm < 0:
        parser.error(f"--warm must be 0 or more, got {args.warm}")
    if args.child:
        print(json.dumps(_child(args.scenes[0], args.method[0] if args.method else None)), flush=True)
        gc.freeze()
        return 0
    reports = []
    for scene in args.scenes:
        for method in args.method or [None]:
            try:
                report = measure(scene, method, args.warm)
            except RuntimeError as error:   # e.g. ccd refuses a scene of polygons: the others still run
                print(f"{scene:<15} {method or '(own)':<9} could not run: {error}", flush=True)
                continue
            reports.append(report)
            print(format_row(report), flush=True)
            if args.top:
                print(format_functions(report, args.top), flush=True)
            if args.json:   # after every run: a long series keeps what it measured
                with open(args.json, "w") as f:
                    json.dump(reports, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
