"""The player: plays trajectories into panels of a canvas. It never simulates.

A panel pulls blocks of a Trajectory (a Trajectory is its own single block) as video time
advances, so memory holds one block per panel however long the video is. A panel sampled at
its own fps shows its latest sample at each video frame (a 15 fps panel in a 60 fps video
holds each sample for four video frames).
"""
from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, field
from typing import Callable, Iterator

import numpy as np

from .. import palette
from ..core.kinds import CIRCLE, SUPPORT
from ..model.scene import RenderSettings
from ..model.trajectory import Events, PastEvents
from . import explain, raster
from .hud import draw_hud, hud_lines
from .layout import CAP_SHARE, HERSHEY_CAP, Layout, Placed, min_text_pixels
from .view import View

TITLE_HEIGHT = 36
HUD_HEIGHT = 26
FLASH_SECONDS = 0.12


@dataclass
class FrameState:
    """What an overlay or the HUD may read about the sample a panel shows.

    positions, velocities: (n, 2); angles: (n,); candidates, pair_collisions: of this sample;
    total_collisions: all collisions so far; approximate_frames: samples so far that the method
    could not finish exactly (Trajectory.approximate); events: the run's collisions up to the
    sample's time (Events; the first MAX_EVENTS, as Trajectory.events keeps them; for a panel
    with no overlay, explainer or counters, only those of the sample's block); counters: the
    running RenderSettings.counters; hierarchy (4,): the sample's pairs passing each bounding
    volume level (Trajectory.hierarchy), or None;
    layout: where this frame's labels go (render/layout.py): an overlay or figure that writes
    text places it there, clear of the box, the bodies and the labels placed before;
    memory: a dict kept for the panel's whole play (the same at every sample, new for every
    play), where an explainer keeps the moments its functions answered first and a scene's
    functions may keep what they read once (a velocity at the impact's sample)."""
    time: float
    sample: int
    positions: np.ndarray
    velocities: np.ndarray
    angles: np.ndarray
    candidates: int
    pair_collisions: int
    total_collisions: int
    approximate_frames: int
    events: Events
    counters: dict = field(default_factory=dict)
    clock: float = 0.0   # seconds of video into the panel (differs from time in slow motion and freezes)
    hierarchy: np.ndarray = None
    memory: dict = field(default_factory=dict)
    layout: object = None


class Memory(dict):
    """FrameState.memory, which notes whether it was read or written since `touched` was last
    cleared: a still (Timeline.draw_alone) draws its frame without the frames before it only
    when nothing drawn at that frame reads what earlier frames kept."""
    touched = False


def _touching(name: str):
    method = getattr(dict, name)

    def touching(self, *args, **kwargs):
        self.touched = True
        return method(self, *args, **kwargs)
    return touching


for _name in ("__getitem__", "__setitem__", "__delitem__", "__contains__", "__iter__", "__len__", "get",
              "setdefault", "pop", "popitem", "update", "keys", "values", "items", "clear", "copy"):
    setattr(Memory, _name, _touching(_name))


@dataclass
class PanelSource:
    """One panel to play: its trajectory blocks (made when the panel starts), how to draw them,
    its title, and its length in samples after the first (frames) at fps."""
    blocks: Callable[[], Iterator]
    settings: RenderSettings
    title: str
    frames: int
    fps: float


@dataclass
class Chapter:
    """Panels played side by side for `frames` video frames."""
    panels: list
    frames: int
    layout: tuple = None


class PanelPlayer:
    """Plays one panel's trajectory into a rectangle of the canvas."""

    def __init__(self, source: PanelSource, rect: tuple, video_fps: float, video_frames: int | None = None,
                 frame_height: int | None = None):
        self.source, self.settings, self.title, self.video_fps = source, source.settings, source.title, video_fps
        self.rect, self.video_frames = rect, video_frames
        left, top, width, height = rect
        # title and HUD grow with tall panels and with the frame (a panel of a 1080p frame is seen
        # at the frame's size, so it draws as the same panel of a 480p frame, scaled)
        frame_height = height if frame_height is None else frame_height
        self.frame_height = frame_height
        self.grow = max(1.0, height / explain.BASE_HEIGHT, frame_height / explain.BASE_HEIGHT)
        title_height = int(round(TITLE_HEIGHT * self.grow)) if self.title else 0
        hud_height = int(round(HUD_HEIGHT * self.grow)) if self.settings.hud else 0
        self.content = (left, top + title_height, width, height - title_height)
        self._blocks = source.blocks()
        self._block = next(self._blocks)
        self.world = self._block.world
        if self.settings.explainer is not None:
            self.settings.explainer.check_bodies(self.world.n)
        # an explainer's caption strips sit above and below the simulation, never over it
        top_lines, bottom_lines = self.settings.explainer.strips() if self.settings.explainer else (0, 0)
        room = height - title_height - hud_height
        self.unit = explain.panel_unit(height, room, top_lines + bottom_lines, frame_height)
        top_h = top_lines * explain.line_height(self.unit)
        bottom_h = bottom_lines * explain.line_height(self.unit)
        self.strips = {"top": (left, top + title_height, width, top_h),
                       "bottom": (left, top + height - hud_height - bottom_h, width, bottom_h)}
        # a side column for figures (a chart beside the simulation), at the right
        side = int(round(width * self.settings.explainer.side)) if self.settings.explainer else 0
        middle = height - title_height - top_h - bottom_h - hud_height
        self.strips["side"] = (left + width - side, top + title_height + top_h, side, middle)
        self.view = View(self.world.box, (left, top + title_height + top_h, width - side, middle))
        self.strips["box"] = self.view.rect   # figures drawn over the simulation itself
        # the HUD's smallest readable scale (render/layout.py): it drops items before going below
        self.least_scale = min_text_pixels(frame_height) * CAP_SHARE / HERSHEY_CAP
        self.text_scale = max(self.least_scale, max(0.38, min(0.55, width / self.grow / 1280 * 0.8)) * self.grow)
        self.layout, self.hud = None, None   # this frame's labels, and the HUD's (text, rectangle, scale)
        self._first, self._sample, self._collisions, self.approximate_frames = 0, -1, 0, 0
        self._history = deque(maxlen=max(self.settings.trails, 1))
        # the run's events so far, for what reads state.events (overlays, explainers, counters);
        # without them, a panel holds only its current block's, however long the video
        settings = self.settings
        self._past = PastEvents() if settings.overlay or settings.explainer or settings.counters else None
        self._recent = []
        self._keep_events()
        self._counters = dict.fromkeys(self.settings.counters, 0)
        self._memory = Memory()   # FrameState.memory
        self.state = None
        self.pace, self.clock = self.settings.pace, 0.0   # render/pace.py: slow motion, freezes
        # the last sample the video shows, so the HUD's last frame reads "frame N/N"
        self.last_sample = source.frames if video_frames is None else self._sample_at(video_frames - 1)
        self._map_coverage = None   # the map's pixels on the canvas, computed at the first draw
        # the circles' sizes and colours in pixels, once: they do not change (None: all are circles)
        circles = np.flatnonzero(self.world.shapes == CIRCLE)
        self._circles = None if len(circles) == self.world.n else circles
        self.settings.check_colors(self.world.n)
        self.colors = self.world.colors if self.settings.colors is None else self.settings.colors
        self._disc_style = raster.disc_style(self.view.length(self.world.radii[circles]), self.colors[circles])

    @property
    def profile(self) -> dict:
        return self._block.profile

    @property
    def waited(self) -> float:
        """Seconds spent waiting for the engine's blocks (engine/ahead.py computes them on a
        thread of their own; 0 for a trajectory played whole)."""
        return getattr(self._blocks, "waited", 0.0)

    def close(self) -> None:
        """Stop the engine computing blocks this panel will not play."""
        close = getattr(self._blocks, "close", None)
        if close is not None:
            close()

    @property
    def warnings(self) -> list:
        return self._block.warnings

    def advance(self, video_frame: int) -> None:
        """Move to the sample shown at this video frame (never backwards), visiting every
        sample on the way so trails, counts and counters build up."""
        target = self._sample_at(video_frame)
        self.clock = video_frame / self.video_fps
        while self._sample < target:
            self._sample += 1
            row = self._row(self._sample)
            self._collisions += int(self._block.collisions[row])
            self.approximate_frames += bool(self._block.approximate[row])
            self._history.append(self._block.positions[row])
            before, self.state = self.state, self._state(row)
            if before is not None:
                for name, count in self.settings.counters.items():
                    self._counters[name] += int(count(before, self.state))
            self.state.counters = dict(self._counters)

    def _sample_at(self, video_frame: int) -> int:
        """The sample shown at a video frame: the latest at the panel's clock (paced)."""
        clock = video_frame / self.video_fps
        shown = self.pace.simulation_time(clock) if self.pace is not None else clock
        return min(int(math.floor(shown * self.source.fps + 1e-9)), self.source.frames)

    def _row(self, sample: int) -> int:
        while sample >= self._first + len(self._block.times):
            self._first += len(self._block.times)
            self._block = next(self._blocks)
            self._keep_events()
        return sample - self._first

    def _keep_events(self) -> None:
        """Keep the new block's events: for the flashes, and with the run's past if it is read."""
        self._recent = self._flashing(self._recent) + [self._block.events]
        if self._past is not None:
            self._past.add(self._block.events)

    def _state(self, row: int) -> FrameState:
        b = self._block
        now = b.times[row] + 1e-12
        past = b.events.between(-np.inf, now) if self._past is None else self._past.up_to(now)
        return FrameState(float(b.times[row]), self._sample, b.positions[row], b.velocities[row], b.angles[row],
                          int(b.candidates[row]), int(b.pair_collisions[row]), self._collisions,
                          self.approximate_frames, past, hierarchy=b.hierarchy[row], memory=self._memory)

    def draw_reads_memory(self, canvas) -> bool:
        """draw, and say whether the drawing read or wrote state.memory (what earlier frames kept)."""
        self._memory.touched = False
        self.draw(canvas)
        return self._memory.touched

    def again(self) -> "PanelPlayer":
        """A new player of the same panel, from its first sample, drawn at the same scale."""
        return PanelPlayer(self.source, self.rect, self.video_fps, self.video_frames, self.frame_height)

    def rehearse(self, scratch) -> None:
        """What the overlay and the explainer keep from this frame (state.memory), as the video
        gives them this frame: they are called as draw calls them, over a scratch canvas."""
        settings, state = self.settings, self.state
        state.clock = self.clock
        if settings.overlay is not None:
            settings.overlay(scratch, self.view, state)
        if settings.explainer is not None:
            settings.explainer.draw(scratch, self.view, state, self.world, self.strips, self.unit)

    def draw(self, canvas) -> None:
        world, settings, state = self.world, self.settings, self.state
        if self.title:
            left, top, width, _ = self.rect
            raster.draw_text(canvas, self.title, (left + width // 2, top + int(round(26 * self.grow))),
                             scale=self.text_scale * 1.25, thickness=max(2, int(round(2 * self.grow))),
                             anchor="center")
        if world.map is not None:
            if self._map_coverage is None:
                self._map_coverage = raster.map_coverage(self.view, world.map, canvas.shape)
            raster.draw_map(canvas, self.view, world.map, self._map_coverage)
        raster.draw_box(canvas, self.view, world.box)
        raster.draw_segments(canvas, self.view, world.segments)
        # trails, arrows and impact rings are drawn into the box's pixels only
        clip = raster.box_clip(canvas, self.view, world.box)
        inside, corner = raster.box_region(canvas, clip)
        line = max(2, int(round(2 * self.unit)))   # survives H.264 at -ql, and grows with the frame
        if settings.trails:
            raster.draw_trails(inside, self.view, np.array(self._history), self.colors, line, corner)
        positions = state.positions if self._circles is None else state.positions[self._circles]
        raster.draw_styled_circles(canvas, self.view.to_pixels(positions), self._disc_style)
        if self._circles is not None:
            outlines, bodies = raster.polygon_outlines(world, state.positions, state.angles)
            raster.draw_polygons(canvas, [self.view.to_pixels(o) for o in outlines], self.colors[bodies])
        if settings.flash:
            self._draw_flashes(canvas, clip, state.time)
        if settings.arrows:
            raster.draw_arrows(inside, self.view, state.positions, state.velocities, settings.arrow_seconds,
                               world.radii, thickness=line, offset=corner, box=world.box)
        state.clock = self.clock   # overlays and explainers may follow the video's clock (freezes)
        self.layout = state.layout = self._layout(state)
        if settings.overlay is not None:
            settings.overlay(canvas, self.view, state)
        if settings.explainer is not None:
            settings.explainer.draw(canvas, self.view, state, world, self.strips, self.unit)
        if settings.hud:
            lines = hud_lines(self._block, self.last_sample, state, compact=self.rect[2] < 800)
            self.hud = draw_hud(canvas, self.content, lines, self.text_scale, self.least_scale)

    def _layout(self, state) -> Layout:
        """The frame's layout: with the box, the segments and the bodies as obstacles for a
        panel whose overlay or explainer may place labels; else empty (nothing is placed)."""
        if self.settings.overlay is None and self.settings.explainer is None:
            return Layout(self.view.rect)
        return Layout.of_frame(self.view, self.world, state.positions, self.unit)

    @property
    def placed(self) -> list:
        """The labels of the frame drawn last (render/layout.py's Placed), and its HUD's line."""
        labels = list(self.layout.placed) if self.layout is not None else []
        if self.hud is not None:
            text, rect, scale = self.hud
            labels.append(Placed("hud", text, rect, None, scale * HERSHEY_CAP / CAP_SHARE, self.content))
        return labels

    def _flashing(self, blocks: list) -> list:
        """The blocks of events that may still flash when the next block starts: those with an
        event within FLASH_SECONDS of the current block's first sample (a block may be one
        frame long: a million bodies stream one frame a block)."""
        since = self._block.times[0] - FLASH_SECONDS
        return [events for events in blocks if len(events) and events.time[-1] >= since]

    def _draw_flashes(self, canvas, clip, now: float) -> None:
        """A ring growing from each fresh impact's contact point, clipped to the box's pixels
        (`clip`, box_clip): a wall's contact point is on the wall, and half a ring outside would
        cover the frame."""
        for events in self._recent:
            events = events.between(now - FLASH_SECONDS, now + 1e-12)
            # a support carrying a body at rest is no impact: it does not flash
            fresh = events.kind != SUPPORT
            if not fresh.any():
                continue
            age = (now - events.time[fresh]) / FLASH_SECONDS
            radii = self.view.length(self.world.radii[events.i[fresh]]) * (0.3 + 0.5 * age)
            centres = self.view.to_pixels(events.point[fresh])
            raster.draw_rings(canvas, centres, radii, palette.FLASH, max(1, int(round(self.unit))), clip)
