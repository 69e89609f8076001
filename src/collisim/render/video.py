"""Play chapters of panels into a video file (or one frame into a PNG). No simulation here:
the player draws the trajectories it is handed (see collisim/pipeline.py for the whole flow)."""
from __future__ import annotations

import sys
import time
import warnings
from pathlib import Path

import numpy as np

from ..io.writers import check_writable, open_writer, write_png, writer_for
from .player import Timeline

MIN_SIZE = 64
QUALITY_FACTORS = {"l": 480 / 720, "m": 1.0, "h": 1.5}


def output_size(base_size: tuple, size, quality: str) -> tuple:
    """The frame size: explicit, else base_size (the scene's) scaled by quality (l 480p, m 720p,
    h 1080p). Odd sizes become even (H.264 with yuv420p needs even sizes), with a warning."""
    if quality not in QUALITY_FACTORS:
        raise ValueError(f"unknown quality '{quality}'; choose one of: {', '.join(QUALITY_FACTORS)}")
    if size is None:  # a preset: scale the scene's size and keep it even without a word
        size = tuple(2 * int(round(s * QUALITY_FACTORS[quality] / 2)) for s in base_size)
    width, height = (int(s) for s in size)
    if width < MIN_SIZE or height < MIN_SIZE:
        raise ValueError(f"size {width}x{height} is too small; the minimum is {MIN_SIZE}x{MIN_SIZE}")
    even = (width + width % 2, height + height % 2)
    if even != (width, height):
        warnings.warn(f"size {width}x{height} rounded to {even[0]}x{even[1]} (H.264 needs even sizes)",
                      stacklevel=3)
    return even


def check_output(path: Path, frames: int, codec: str, png_frame) -> None:
    """Raise ValueError for an output that cannot be written, before anything is simulated."""
    if png_frame is not None and not 0 <= png_frame < frames:
        raise ValueError(f"frame {png_frame} is out of range: the video has frames 0..{frames - 1}")
    check_writable(path.parent)
    if png_frame is None:
        writer_for(codec)


def play(chapters: list, fps: float, frames: int, path: Path, size: tuple, *, codec: str = "h264",
         quality: str = "m", png_frame: int | None = None, progress: bool = False, profile: dict | None = None) -> Path:
    """Draw `frames` video frames of the chapters into `path` (or frame png_frame into a PNG);
    when the chapters are shorter, the last one's last frame holds.

    `profile`, when given a dict, receives the seconds spent per phase: the simulation phases
    reported by the trajectories' blocks, plus draw and encode."""
    timeline = Timeline(chapters, size, fps)
    if png_frame is not None:
        canvas = np.empty((size[1], size[0], 3), np.uint8)
        for frame in range(png_frame + 1):  # walk the frames so trails, counts and chapters build up
            timeline.draw(canvas, frame)
        write_png(path, canvas)
        return path
    bar = _progress_bar(frames, path.name) if progress else None
    draw_seconds = 0.0
    with open_writer(codec, path, fps, size, quality) as video:
        for frame in range(frames):
            canvas = video.frame_buffer()
            start = time.perf_counter()
            timeline.draw(canvas, frame)
            draw_seconds += time.perf_counter() - start
            video.write(canvas)
            if bar is not None:
                bar.update(1)
    if bar is not None:
        bar.close()
    if profile is not None:
        for phase, seconds in timeline.profile().items():
            profile[phase] = profile.get(phase, 0.0) + seconds
        simulated = sum(profile.values())
        profile["draw"] = draw_seconds - simulated  # drawing includes pulling streamed blocks from the engine
        profile["encode"] = video.encode_seconds  # on the encoder's thread, overlapping the drawing
    return path


def _progress_bar(total: int, label: str):
    from tqdm import tqdm
    return tqdm(total=total, desc=label, unit="frame", file=sys.stderr, dynamic_ncols=True, leave=False)
