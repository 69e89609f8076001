"""Play chapters of panels into a writer (or one frame into a PNG). No simulation here: the player
draws the trajectories it is handed (see collisim/pipeline.py for the whole flow).

Also the render's settings that are not the scene's: quality presets (manim's -ql -qm -qh -qk),
the limits, the background colour, and the progress bar with its first-run line.
"""
from __future__ import annotations

import sys
import time
import warnings
from contextlib import nullcontext
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from numba.core import event as numba_event

from .. import palette
from ..io.writers import open_writer, write_png
from ..core.checks import number
from . import bands
from .timeline import Timeline
from .raster import bgr


@dataclass(frozen=True)
class Quality:
    label: str      # manim's name for it, also the default output's file name
    height: int     # frame height; the width keeps the scene's aspect ratio
    fps: float      # the video's frame rate (the simulation keeps the scene's own step)


QUALITIES = {"l": Quality("480p15", 480, 15), "m": Quality("720p30", 720, 30),
             "h": Quality("1080p60", 1080, 60), "k": Quality("2160p60", 2160, 60)}
MIN_SIZE = 64
MAX_SIZE = (7680, 4320)   # 8K UHD: the longer side, the shorter side
MAX_FRAMES = 100_000      # about 28 minutes at 60 fps
MAX_STEPS = 10_000_000    # simulation steps of one scene (a 100 000-frame video at 4 x 60 fps, 25 substeps)


def _check_quality(quality) -> None:
    if quality is not None and quality not in QUALITIES:
        raise ValueError(f"unknown quality '{quality}'; choose one of: {', '.join(QUALITIES)}")


def output_size(base_size: tuple, size, quality: str | None) -> tuple:
    """The frame size: explicit; else a quality's height (l 480, m 720, h 1080, k 2160) at the
    aspect ratio of base_size (the scene's: 1280x720 becomes manim's 854x480 ... 3840x2160); else
    base_size itself. Odd sizes become even (H.264 with yuv420p needs even sizes), with a warning."""
    _check_quality(quality)
    if size is None and quality is not None:  # a preset: keep it even without a word
        height = QUALITIES[quality].height
        size = (2 * int(round(base_size[0] * height / base_size[1] / 2)), height)
    width, height = (int(s) for s in (size or base_size))
    if width < MIN_SIZE or height < MIN_SIZE:
        raise ValueError(f"size {width}x{height} is too small; the minimum is {MIN_SIZE}x{MIN_SIZE}")
    even = (width + width % 2, height + height % 2)
    if even != (width, height):
        warnings.warn(f"size {width}x{height} rounded to {even[0]}x{even[1]} (H.264 needs even sizes)",
                      stacklevel=3)
    return even


def video_fps(scene_fps: float, fps, quality: str | None) -> float:
    """The video's frame rate: explicit, else the quality's (15, 30, 60, 60), else the scene's."""
    _check_quality(quality)
    if fps is None:
        fps = QUALITIES[quality].fps if quality is not None else scene_fps
    return number("fps", fps, positive=True)


def check_limits(size: tuple, frames: int) -> None:
    """ValueError for a frame larger than 8K or a video of more than MAX_FRAMES frames: almost
    always a typo (a size or --seconds with a digit too many) that would run for hours."""
    width, height = size
    if max(width, height) > MAX_SIZE[0] or min(width, height) > MAX_SIZE[1]:
        raise ValueError(f"size {width}x{height} is larger than {MAX_SIZE[0]}x{MAX_SIZE[1]}; "
                         f"use --no-limits to render it anyway")
    if frames > MAX_FRAMES:
        raise ValueError(f"the video would have {_count(frames)} frames, more than {MAX_FRAMES}; "
                         f"use --no-limits to render it anyway")


def check_steps(scene) -> None:
    """ValueError for a scene, or a panel or chapter of it, whose simulation would take more
    than MAX_STEPS steps (frames times discrete substeps): a physics frame rate or substep
    count with digits too many (--physics-fps 1e12 ran for ever) rather than a demo."""
    if scene.world is None:
        for part in [panel.scene for panel in scene.panels] + list(scene.chapters):
            check_steps(part)
        return
    substeps = scene.substeps if scene.method == "discrete" else 1
    steps = scene.frames * substeps
    if steps > MAX_STEPS:
        per_frame = f" of {substeps} substeps" if substeps > 1 else ""
        raise ValueError(f"scene '{scene.name}' would take {_count(steps)} simulation steps ({_count(scene.frames)} "
                         f"frames at {scene.fps:g} fps{per_frame}), more than {MAX_STEPS}; use --no-limits to run it "
                         f"anyway")


def _count(k: int) -> str:
    """A count as a line says it: every digit up to 15 of them, else three significant digits
    (--physics-fps 1e300 made a count of 300 digits, printed twice)."""
    return str(k) if k < 10 ** 15 else f"{k:.3g}"


THEMES = palette.THEMES


def make_theme(theme: str | None = None, background=None) -> palette.Theme:
    """The theme to draw with (palette.THEMES), its background replaced by `background`
    ('#RRGGBB' or an RGB triple) when given. Without a theme, a background chooses the one
    whose text reads on it (palette.theme_for: white gets the light theme's dark text), and no
    background the dark theme."""
    if theme is not None and theme not in THEMES:
        raise ValueError(f"unknown theme '{theme}'; choose one of: {', '.join(THEMES)}")
    if background is None:
        return THEMES[theme or "dark"]
    rgb = palette.parse_color(background, "background")
    return THEMES[theme or palette.theme_for(rgb)].with_background(rgb)


COMPILING = "collisim: compiling the simulation kernels (first run only) …"


class Progress:
    """The progress bar on stderr, and the one line that says the kernels are compiling.

    Cold or warm is numba's own answer: its dispatcher fires a "numba:compile" event only when
    it compiles a kernel, never when it loads one from its cache (the __pycache__ next to the
    sources, or $NUMBA_CACHE_DIR). So the line appears exactly when a compile happens — first
    run, a fresh cache folder, a new numba version — costs nothing on a warm run, and is never
    a guess from timing. It is printed when compiling starts, before the bar exists: the bar
    starts once the first frame is drawn (its kernels compiled and its first block simulated).
    A later compile (a chapter under another method) clears the bar, and its time is taken out
    of the bar's clock, so rate and ETA measure rendering only; `compile_seconds` is the total.

        with Progress(bar=True) as progress:   # listens for compiles while open
            ... progress.step(total, label) after each frame ...
    """

    def __init__(self, bar: bool = True, stream=None):
        self.show_bar, self.stream = bar, stream or sys.stderr
        self.bar, self.compile_seconds, self.compiled = None, 0.0, False
        self._depth, self._since = 0, 0.0
        self._listener = _CompileListener(self)

    def __enter__(self):
        numba_event.register("numba:compile", self._listener)
        self._show_warning, warnings.showwarning = warnings.showwarning, self._show_warning_below_bar
        return self

    def __exit__(self, *exc):
        numba_event.unregister("numba:compile", self._listener)
        warnings.showwarning = self._show_warning
        self.close()
        return False

    def _show_warning_below_bar(self, *args, **kwargs) -> None:
        if self.bar is not None:
            self.bar.clear()   # the bar draws itself again at its next step
        self._show_warning(*args, **kwargs)

    def step(self, total: int, label: str) -> None:
        """One more frame done (the first starts the bar)."""
        if not self.show_bar:
            return
        if self.bar is None:
            from tqdm import tqdm
            self.bar = tqdm(total=total, initial=1, desc=label, unit="frame", file=self.stream,
                            dynamic_ncols=True, leave=False)
        else:
            self.bar.update(1)

    def close(self) -> None:
        """Remove the bar and its line (leave nothing for the next line to overwrite)."""
        if self.bar is not None:
            self.bar.close()
            self.bar = None

    def compile_started(self) -> None:
        if self._depth == 0:
            self._since = time.perf_counter()
            if not self.compiled:
                if self.bar is not None:
                    self.bar.clear()
                print(COMPILING, file=self.stream, flush=True)
            self.compiled = True
        self._depth += 1

    def compile_ended(self) -> None:
        self._depth -= 1
        if self._depth == 0:
            self.compile_seconds += time.perf_counter() - self._since
            if self.bar is not None:
                self.bar.unpause()   # the compile is not rendering: keep it out of rate and ETA


class _CompileListener(numba_event.Listener):
    """numba calls on_start/on_end around each kernel it compiles (nested for the kernels a
    kernel calls)."""

    def __init__(self, progress: Progress):
        self.progress = progress

    def on_start(self, event) -> None:
        self.progress.compile_started()

    def on_end(self, event) -> None:
        self.progress.compile_ended()


def play(chapters: list, fps: float, frames: int, path: Path, size: tuple, *, codec: str = "h264",
         quality: str = "m", png_frame: int | None = None, transparent: bool = False,
         theme: palette.Theme = palette.THEMES["dark"], name: str | None = None, progress=False,
         profile: dict | None = None) -> Path:
    """Draw `frames` video frames of the chapters into `path` with the writer `codec` (or frame
    png_frame into a PNG); when the chapters are shorter, the last one's last frame holds.

    `theme` gives the colours (palette.Theme); with `transparent` its background gets alpha 0.
    `progress`: False, True (a bar and the compile line on stderr), or a Progress already open.
    `profile`, when given a dict, receives the seconds spent per phase: the simulation phases
    reported by the trajectories' blocks, plus draw and encode."""
    with palette.using(theme):
        return _play(chapters, fps, frames, path, size, codec, quality, png_frame, transparent, name, progress,
                     profile)


def _play(chapters, fps, frames, path, size, codec, quality, png_frame, transparent, name, progress, profile):
    timeline = Timeline(chapters, size, fps)
    background_bgr = bgr(palette.BACKGROUND)   # the canvas each frame starts from (Timeline's)
    own = progress is True
    progress = Progress() if own else (progress or Progress(bar=False))
    with progress if own else nullcontext():
        try:
            if png_frame is not None:
                canvas = np.empty((size[1], size[0], 3), np.uint8)
                # simulated up to the frame, drawn alone (a panel whose overlay keeps memory replays
                # its chapter's frames for it, drawing nothing but that overlay: the bar counts those)
                timeline.draw_alone(canvas, png_frame, step=lambda done, total: progress.step(total, path.name))
                write_png(path, canvas, background_bgr if transparent else None)
            else:
                draw_seconds = 0.0
                with open_writer(codec, path, fps, size, quality, transparent=transparent,
                                 background=background_bgr, name=name, frames=frames) as video, \
                        bands.on_one_thread():
                    for frame in range(frames):
                        canvas = video.frame_buffer()
                        start = time.perf_counter()
                        timeline.draw(canvas, frame)
                        draw_seconds += time.perf_counter() - start
                        video.write(canvas)
                        progress.step(frames, path.name)
        finally:
            timeline.close()
            progress.close()
    if profile is not None and png_frame is None:
        for phase, seconds in timeline.profile().items():   # on the engine's thread (engine/ahead.py)
            profile[phase] = profile.get(phase, 0.0) + seconds
        profile["draw"] = draw_seconds - timeline.waited()  # less the time the engine kept the drawing waiting
        profile["encode"] = video.encode_seconds  # on the encoder's thread, overlapping the drawing
    summary = timeline.approximate_summary()
    if summary:
        warnings.warn(summary, stacklevel=3)
    return path
