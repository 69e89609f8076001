"""Render a scene: play its simulations frame by frame into panels, draw, encode.

Each panel pulls blocks of frames from the engine's stream as video time advances, so memory
holds one block per panel however long the video is. A panel simulated at its own fps shows
its latest sample at each video frame (a 15 fps panel in a 60 fps video holds each sample for
four video frames).
"""
from __future__ import annotations

import math
import sys
import time
import warnings
from collections import deque
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from .. import palette
from ..engine.simulate import stream
from ..scene import Panel, Scene
from . import raster
from .encoder import VideoWriter, check_codec, check_writable, write_png
from .hud import draw_hud, hud_lines
from .view import View

MIN_SIZE = 64
TITLE_HEIGHT = 36
HUD_HEIGHT = 26
FLASH_SECONDS = 0.12


@dataclass
class FrameState:
    """What an overlay or the HUD may read about the sample shown in a panel."""
    time: float
    sample: int
    positions: np.ndarray
    velocities: np.ndarray
    candidates: int
    pair_hits: int
    total_collisions: int


class PanelPlayer:
    """Plays one simulation into a rectangle of the canvas."""

    def __init__(self, scene: Scene, rect: tuple, title: str, video_fps: float, phases: bool = False):
        self.scene, self.title, self.video_fps = scene, title, video_fps
        self.rect = rect
        left, top, width, height = rect
        title_height = TITLE_HEIGHT if title else 0
        hud_height = HUD_HEIGHT if scene.render.hud else 0
        self.content = (left, top + title_height, width, height - title_height)
        self.view = View(scene.world.box, (left, top + title_height, width, height - title_height - hud_height))
        self.colors = scene.world.colors
        self.text_scale = max(0.38, min(0.55, width / 1280 * 0.8))
        self._blocks = stream(scene, phases=phases)
        self._block = next(self._blocks)
        self._first = 0
        self._sample = -1
        self._collisions = 0
        self._history = deque(maxlen=max(scene.render.trails, 1))
        self._recent = []

    @property
    def profile(self) -> dict:
        return self._block.profile

    def advance(self, video_frame: int) -> None:
        """Move to the sample shown at this video frame (never backwards)."""
        target = min(int(math.floor(video_frame * self.scene.fps / self.video_fps + 1e-9)), self.scene.frames)
        while self._sample < target:
            self._sample += 1
            row = self._row(self._sample)
            self._collisions += int(self._block.collisions[row])
            self._history.append(self._block.positions[row])
        self.state = self._state(self._row(self._sample))

    def _row(self, sample: int) -> int:
        while sample >= self._first + len(self._block.times):
            self._first += len(self._block.times)
            self._block = next(self._blocks)
            self._recent = self._recent[-1:] + [self._block.events]
        if not self._recent:
            self._recent = [self._block.events]
        return sample - self._first

    def _state(self, row: int) -> FrameState:
        b = self._block
        return FrameState(float(b.times[row]), self._sample, b.positions[row], b.velocities[row],
                          int(b.candidates[row]), int(b.pair_hits[row]), self._collisions)

    def draw(self, canvas, video_frame: int, video_frames: int) -> None:
        world, settings, state = self.scene.world, self.scene.render, self.state
        if self.title:
            left, top, width, _ = self.rect
            raster.draw_text(canvas, self.title, (left + width // 2, top + 26), scale=self.text_scale * 1.25,
                             thickness=2, anchor="center")
        raster.draw_box(canvas, self.view, world.box)
        raster.draw_segments(canvas, self.view, world.segments)
        if settings.trails:
            raster.draw_trails(canvas, self.view, np.array(self._history), self.colors)
        raster.draw_circles(canvas, self.view.to_pixels(state.positions), self.view.length(world.radii), self.colors)
        if settings.flash:
            self._draw_flashes(canvas, state.time)
        if settings.arrows:
            raster.draw_arrows(canvas, self.view, state.positions, state.velocities, settings.arrow_seconds)
        if settings.overlay is not None:
            settings.overlay(canvas, self.view, state)
        if settings.hud:
            draw_hud(canvas, self.content, hud_lines(self.scene, state, compact=self.rect[2] < 800),
                     self.text_scale)

    def _draw_flashes(self, canvas, now: float) -> None:
        for events in self._recent:
            fresh = (events.time <= now + 1e-12) & (events.time > now - FLASH_SECONDS)
            if not fresh.any():
                continue
            age = (now - events.time[fresh]) / FLASH_SECONDS
            radii = self.view.length(self.scene.world.radii[events.i[fresh]]) * (0.3 + 0.5 * age)
            raster.draw_rings(canvas, self.view.to_pixels(events.point[fresh]), radii, palette.FLASH, 1)


def panel_rects(count: int, size: tuple, layout=None) -> list:
    """Split the canvas into a grid of equal panels: `layout` (rows, cols), or up to three in a row."""
    width, height = size
    if layout is None:
        cols = count if count <= 3 else math.ceil(count / 2)
        rows = math.ceil(count / cols)
    else:
        rows, cols = layout
    w, h = width // cols, height // rows
    return [((k % cols) * w, (k // cols) * h, w, h) for k in range(count)]


def output_size(scene: Scene, size, quality: str) -> tuple:
    """The frame size: explicit, else the scene's scaled by quality (l 480p, m 720p, h 1080p).
    Odd sizes become even (H.264 with yuv420p needs even sizes), with a warning."""
    if size is None:  # a preset: scale the scene's size and keep it even without a word
        factor = {"l": 480 / 720, "m": 1.0, "h": 1.5}[quality]
        size = tuple(2 * int(round(s * factor / 2)) for s in scene.render.size)
    width, height = (int(s) for s in size)
    if width < MIN_SIZE or height < MIN_SIZE:
        raise ValueError(f"size {width}x{height} is too small; the minimum is {MIN_SIZE}x{MIN_SIZE}")
    even = (width + width % 2, height + height % 2)
    if even != (width, height):
        warnings.warn(f"size {width}x{height} rounded to {even[0]}x{even[1]} (H.264 needs even sizes)",
                      stacklevel=3)
    return even


def render(scene: Scene, path, size=None, *, codec: str = "h264", quality: str = "m",
           png_frame: int | None = None, progress: bool = False, profile: dict | None = None,
           phases: bool = False) -> Path:
    """Render `scene` to an MP4 (or, with png_frame, one frame to a PNG) and return its path.

    The file appears only when complete. Raises ValueError for bad input, before simulating.
    `profile`, when given a dict, receives the seconds spent per phase: simulation phases
    summed over panels, plus draw and encode. `phases` times each phase of the discrete step
    separately (a slower pipeline; otherwise the grid broad phase runs fused as one "step").
    """
    if quality not in ("l", "m", "h"):
        raise ValueError(f"unknown quality '{quality}'; choose one of: l, m, h")
    size = output_size(scene, size, quality)
    path = Path(path)
    if png_frame is not None and not 0 <= png_frame < scene.frames:
        raise ValueError(f"frame {png_frame} is out of range: the scene has frames 0..{scene.frames - 1}")
    check_writable(path.parent)
    if png_frame is None:
        check_codec(codec)
    timeline = Timeline(scene, size, phases=phases)
    if png_frame is not None:
        canvas = np.empty((size[1], size[0], 3), np.uint8)
        timeline.draw(canvas, png_frame, walk=True)
        write_png(path, canvas)
        return path
    bar = _progress_bar(scene.frames, path.name) if progress else None
    draw_seconds = 0.0
    with VideoWriter(path, scene.fps, size, codec, quality) as video:
        for frame in range(scene.frames):
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
        profile["draw"] = draw_seconds - simulated  # drawing includes pulling frames from the engine
        profile["encode"] = video.encode_seconds  # on the encoder's thread, overlapping the drawing
    return path


class Timeline:
    """Which chapter, and which of its frames, each video frame shows."""

    def __init__(self, scene: Scene, size: tuple, phases: bool = False):
        self.size, self.phases = size, phases
        self.background = np.empty((size[1], size[0], 3), np.uint8)
        self.background[:] = raster.bgr(palette.BACKGROUND)
        self.chapters = scene.chapters or (scene,)
        self.starts = np.cumsum([0] + [c.frames for c in self.chapters])
        self._index, self._players, self._finished = -1, [], []

    def draw(self, canvas, frame: int, walk: bool = False) -> None:
        index = min(int(np.searchsorted(self.starts, frame, side="right")) - 1, len(self.chapters) - 1)
        chapter = self.chapters[index]
        if index != self._index:
            self._finished.extend(self._players)
            self._index, self._players = index, make_players(chapter, self.size, self.phases)
        local = min(frame - int(self.starts[index]), chapter.frames - 1)
        np.copyto(canvas, self.background)  # a plain copy: filling with a colour is ten times slower
        draw_frame(canvas, self._players, local, chapter.frames, advance_to=local if walk else None)

    def profile(self) -> dict:
        total = {}
        for player in self._finished + self._players:
            for phase, seconds in player.profile.items():
                total[phase] = total.get(phase, 0.0) + seconds
        return total


def make_players(scene: Scene, size: tuple, phases: bool = False) -> list:
    panels = scene.panels or (Panel(scene, ""),)
    rects = panel_rects(len(panels), size, scene.render.layout)
    return [PanelPlayer(p.scene, rect, p.title, scene.fps, phases) for p, rect in zip(panels, rects)]


def draw_frame(canvas, players: list, frame: int, frames: int, advance_to: int | None = None) -> None:
    """Draw video frame `frame` of the players over the canvas's background."""
    for player in players:
        if advance_to is not None:
            for k in range(advance_to + 1):  # walk the samples so trails and counts build up
                player.advance(k)
        else:
            player.advance(frame)
        player.draw(canvas, frame, frames)


def _progress_bar(total: int, label: str):
    from tqdm import tqdm
    return tqdm(total=total, desc=label, unit="frame", file=sys.stderr, dynamic_ncols=True, leave=False)


