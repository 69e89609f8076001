"""The whole flow in one place: a scene is simulated (streamed in blocks by the engine) and its
trajectories are handed to the player, which draws them into a writer.

    scene -> engine.stream -> Trajectory blocks -> render.player -> io.writers -> file

`render` takes a Scene, a Trajectory (a saved run, pymunk's run), or a list of
(title, Trajectory) drawn side by side (what `collisim compare --video` shows).
"""
from __future__ import annotations

from pathlib import Path

from .engine import stream
from .model.scene import RenderSettings, Scene
from .model.trajectory import Trajectory
from .render.player import Chapter, PanelSource
from .render.video import check_output, output_size, play


def scene_chapters(scene: Scene) -> list:
    """The chapters of a scene, each a list of panels whose blocks stream from the engine."""
    if scene.chapters:
        return [chapter for part in scene.chapters for chapter in scene_chapters(part)]
    panels = [(p.scene, p.title) for p in scene.panels] or [(scene, "")]
    sources = [PanelSource(lambda s=s: stream(s), s.render, title, s.frames, s.fps) for s, title in panels]
    return [Chapter(sources, scene.frames, scene.render.layout)]


def trajectory_chapters(panels: list, settings: RenderSettings, layout=None) -> list:
    """One chapter of (title, Trajectory) panels."""
    frames = max(t.frames for _, t in panels)
    sources = [PanelSource(lambda t=t: iter([t]), settings, title, t.frames, t.fps) for title, t in panels]
    return [Chapter(sources, frames, layout)]


def render(source, path, size=None, *, settings: RenderSettings | None = None, codec: str = "h264",
           quality: str = "m", png_frame: int | None = None, progress: bool = False,
           profile: dict | None = None) -> Path:
    """Render a Scene, a Trajectory or a list of (title, Trajectory) to a video (or, with
    png_frame, that one frame to a PNG) and return its path.

    The file appears only when complete. `settings` draws trajectories (a scene brings its
    own). Bad input raises ValueError before anything is simulated. `profile`, when given a
    dict, receives seconds per phase: simulation, draw and encode.
    """
    path = Path(path)
    if isinstance(source, Scene):
        chapters, fps, frames, base = scene_chapters(source), source.fps, source.frames, source.render.size
    else:
        panels = [("", source)] if isinstance(source, Trajectory) else list(source)
        if not panels or not all(isinstance(t, Trajectory) for _, t in panels):
            raise ValueError("render takes a Scene, a Trajectory, or a list of (title, Trajectory)")
        settings = settings or RenderSettings()
        chapters = trajectory_chapters(panels, settings, settings.layout)
        fps, frames, base = panels[0][1].fps, chapters[0].frames, settings.size
    size = output_size(base, size, quality)
    check_output(path, frames, codec, png_frame)
    return play(chapters, fps, frames, path, size, codec=codec, quality=quality, png_frame=png_frame,
                progress=progress, profile=profile)
