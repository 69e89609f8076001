"""The timeline: which chapter, and which of its frames, each video frame shows, and the panels
(render/player.py) that draw it, side by side in a grid."""
from __future__ import annotations

import math

import numpy as np

from .. import palette
from ..model.trajectory import approximate_summary
from . import raster
from .player import Chapter, PanelPlayer


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


def make_players(chapter: Chapter, size: tuple, video_fps: float) -> list:
    rects = panel_rects(len(chapter.panels), size, chapter.layout)
    return [PanelPlayer(source, rect, video_fps, chapter.frames, size[1])
            for source, rect in zip(chapter.panels, rects)]


def draw_frame(canvas, players: list, frame: int) -> None:
    """Draw video frame `frame` of the players over the canvas's background."""
    for player in players:
        player.advance(frame)
        player.draw(canvas)


class Timeline:
    """Which chapter, and which of its frames, each video frame shows."""

    def __init__(self, chapters: list, size: tuple, fps: float):
        self.chapters, self.size, self.fps = chapters, size, fps
        self.background = np.empty((size[1], size[0], 3), np.uint8)
        self.background[:] = raster.bgr(palette.BACKGROUND)
        self.starts = np.cumsum([0] + [c.frames for c in chapters])
        self._index, self._players, self._finished = -1, [], []

    def draw(self, canvas, frame: int) -> None:
        index, local = self._locate(frame)
        chapter = self.chapters[index]
        if index != self._index:
            for player in self._players:
                player.close()
            self._finished.extend(self._players)
            self._index, self._players = index, make_players(chapter, self.size, self.fps)
        np.copyto(canvas, self.background)  # a plain copy: filling with a colour is ten times slower
        draw_frame(canvas, self._players, local)

    def draw_alone(self, canvas, frame: int, step=None) -> None:
        """Draw video frame `frame` with the same pixels as draw() would after every frame
        before it, drawing none of them (-s, --png N): the chapters before its own are neither
        simulated nor drawn, and its panels are simulated to the frame and visit every sample
        on the way (trails, flashes, counters and the HUD's counts build up as in the video).

        An overlay or explainer may keep what it saw at earlier frames in state.memory (the
        moment a function first answered, ghosts of past samples). So the frame is drawn
        first as if it were alone; a panel whose drawing read its memory is then played again
        from its chapter's first frame, its overlay and explainer called at every frame over a
        scratch canvas (the bodies, trails and HUD not drawn), and the frame drawn again.
        `step(done, total)` is told of each frame rehearsed."""
        index, local = self._locate(frame)
        chapter = self.chapters[index]
        self.close()
        self._index, self._players = index, make_players(chapter, self.size, self.fps)
        remembering = []
        np.copyto(canvas, self.background)
        for k, player in enumerate(self._players):
            player.advance(local)
            if player.draw_reads_memory(canvas):
                remembering.append(k)
        if not remembering:
            return
        scratch = np.empty_like(canvas)
        for k in remembering:
            old = self._players[k]
            old.close()
            player = self._players[k] = old.again()
            for earlier in range(local):
                player.advance(earlier)
                player.rehearse(scratch)
                if step is not None:
                    step(earlier + 1, local)
            player.advance(local)
        np.copyto(canvas, self.background)
        for player in self._players:   # a panel that read no memory draws the same pixels again
            player.draw(canvas)

    def _locate(self, frame: int) -> tuple:
        """(chapter index, frame within the chapter) of a video frame; past the end, the last
        chapter's last frame holds."""
        index = min(int(np.searchsorted(self.starts, frame, side="right")) - 1, len(self.chapters) - 1)
        return index, min(frame - int(self.starts[index]), self.chapters[index].frames - 1)

    def placed(self) -> list:
        """(panel player, Placed) for every label of the frame drawn last (the tests' geometry)."""
        return [(player, label) for player in self._players for label in player.placed]

    def approximate_summary(self) -> str:
        """One line saying how many of the played frames were approximate, and why; '' if none."""
        players = [p for p in self._finished + self._players if p.approximate_frames]
        if not players:
            return ""
        parts = [approximate_summary(p.approximate_frames, p.source.frames, p.title or "the scene",
                                     p.warnings) for p in players]
        return "; ".join(parts)

    def close(self) -> None:
        """Stop the engine for every panel (at the end of a render, or when it is cut short)."""
        for player in self._finished + self._players:
            player.close()

    def waited(self) -> float:
        """Seconds the players spent waiting for the engine's blocks."""
        return sum(player.waited for player in self._finished + self._players)

    def profile(self) -> dict:
        total = {}
        for player in self._finished + self._players:
            # a copy taken at once: an engine thread stopped early may still be timing a phase
            for phase, seconds in dict(player.profile).items():
                total[phase] = total.get(phase, 0.0) + seconds
        return total
