"""The whole flow in one place: a scene is simulated (streamed in blocks by the engine) and its
trajectories are handed to the player, which draws them into a writer.

    scene -> engine.stream -> Trajectory blocks -> render.player -> io.writers -> file

`render` takes a Scene, a Trajectory (a saved run, pymunk's run), or a list of
(title, Trajectory) drawn side by side (what `collisim compare --video` shows). `plan` settles
what a render will draw — chapters, the video's frame rate, frame count and size — before
anything is simulated; the command line plans first to name its default output.

The video's frame rate and the simulation's step are separate: each panel samples its own
simulation at its own fps, and the player shows, at each video frame, the latest sample (a
60 fps simulation in a 30 fps video shows every other sample; in a 90 fps one some samples
hold for two frames). A quality or --fps changes the video, never the simulation.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass
from pathlib import Path

from .engine import METHODS, stream
from .engine.ahead import Ahead
from .engine.start import check_scene
from .interrupts import ctrl_c_safe
from .io.formats import check_format, output_target
from .io.sequence import check_sequence_folder
from .io.writers import check_writable, remove_empty_folders, writer_for
from .model.scene import RenderSettings, Scene
from .model.trajectory import Trajectory
from .render.player import Chapter, PanelSource
from .render.video import check_limits, check_steps, make_theme, output_size, play, video_fps


GIF_MAX_FPS = 50   # GIF delays are whole hundredths of a second; browsers stretch those under 2


def video_frames(seconds: float, fps: float) -> int:
    """Frames of a video lasting `seconds` at `fps`: round(seconds × fps), at least one."""
    frames = int(round(seconds * fps))
    if frames < 1:
        raise ValueError(f"seconds={seconds:g} at fps={fps:g} is shorter than one frame")
    return frames


def scene_chapters(scene: Scene, fps: float | None = None) -> list:
    """The chapters of a scene, each a list of panels whose blocks stream from the engine. A
    chapter lasts its seconds at the video's frame rate `fps` (default: the scene's); each
    panel keeps its own simulation step."""
    fps = scene.fps if fps is None else fps
    if scene.chapters:
        return [chapter for part in scene.chapters for chapter in scene_chapters(part, fps)]
    panels = [(p.scene, p.title) for p in scene.panels] or [(scene, "")]
    sources = [PanelSource(lambda s=s: Ahead(stream(s, checked=True)), s.render, title, s.frames, s.fps)
               for s, title in panels]
    return [Chapter(sources, video_frames(video_seconds(scene), fps), scene.render.layout)]


def video_seconds(scene: Scene) -> float:
    """How long a scene plays: its seconds, plus what slow motion and freezes add (the longest
    panel's, for panels). A scene of chapters gives the whole video's length itself."""
    if scene.chapters:
        return scene.seconds
    if scene.panels:
        return max([scene.seconds] + [video_seconds(p.scene) for p in scene.panels])
    return scene.seconds + (scene.render.pace.extra if scene.render.pace is not None else 0.0)


def check_colors(scene: Scene) -> None:
    """ValueError for a scene, panel or chapter whose RenderSettings.colors miss a body or have
    one too many, before anything is simulated."""
    if scene.world is not None:
        scene.render.check_colors(scene.world.n)
    for part in [panel.scene for panel in scene.panels] + list(scene.chapters):
        check_colors(part)


def lesson_fps(scene: Scene) -> float | None:
    """The highest RenderSettings.min_fps of a scene and its panels and chapters, or None."""
    parts = [panel.scene for panel in scene.panels] + list(scene.chapters)
    needs = [scene.render.min_fps] + [lesson_fps(part) for part in parts]
    needs = [need for need in needs if need is not None]
    return max(needs) if needs else None


def keep_lesson_rate(rate: float, need: float | None, fps, quality, name: str) -> float:
    """The video rate a quality preset gives, raised to what the scene's lesson needs (its
    min_fps), with a note; an explicit fps, or no preset, is left as it is."""
    if need is None or fps is not None or quality is None or rate >= need:
        return rate
    warnings.warn(f"{name} needs {need:g} fps video to show what it teaches: -q{quality} keeps {need:g} fps "
                  f"(not {rate:g}) and lowers only the size", stacklevel=4)
    return need


def trajectory_chapters(panels: list, settings: RenderSettings, layout=None, fps: float | None = None) -> list:
    """One chapter of (title, Trajectory) panels, as long as the longest at the video's `fps`
    (default: the first trajectory's)."""
    fps = panels[0][1].fps if fps is None else fps
    extra = settings.pace.extra if settings.pace is not None else 0.0
    frames = max(video_frames(t.frames / t.fps + extra, fps) for _, t in panels)
    sources = [PanelSource(lambda t=t: iter([t]), settings, title, t.frames, t.fps) for title, t in panels]
    return [Chapter(sources, frames, layout)]


@dataclass
class Plan:
    """A render settled before anything is simulated. chapters: what the player plays; fps,
    frames, size: the video's; name: the scene's; label: the default output's file name, the
    quality as manim names it (`720p30`: height and video fps) or `WxH` for an explicit size."""
    chapters: list
    fps: float
    frames: int
    size: tuple
    name: str
    label: str


def plan(source, size=None, *, fps=None, quality=None, settings: RenderSettings | None = None,
         name: str | None = None, limits: bool = True) -> Plan:
    """The Plan of rendering a Scene, a Trajectory or a list of (title, Trajectory).

    size: (width, height), else the quality's height at the scene's aspect ratio, else the
    scene's size; fps: the video's frame rate, else the quality's (l 15, m 30, h 60, k 60) but
    no lower than the scene's RenderSettings.min_fps (a warning says so), else the scene's. `limits` refuses frames over 7680x4320, videos over 100 000 frames and scenes
    of more than 10 000 000 simulation steps."""
    if isinstance(source, Scene):
        check_scene(source, METHODS)
        if limits:
            check_steps(source)
        check_colors(source)
        base, own_fps, name = source.render.size, source.fps, name or source.name
        rate = keep_lesson_rate(video_fps(own_fps, fps, quality), lesson_fps(source), fps, quality, name)
        chapters, frames = scene_chapters(source, rate), video_frames(video_seconds(source), rate)
    else:
        panels = [("", source)] if isinstance(source, Trajectory) else list(source)
        if not panels or not all(isinstance(t, Trajectory) for _, t in panels):
            raise ValueError("render takes a Scene, a Trajectory, or a list of (title, Trajectory)")
        settings = settings or RenderSettings()
        for _, trajectory in panels:
            settings.check_colors(trajectory.world.n)
        if settings.arrows and any(t.storage == "positions" for _, t in panels):
            raise ValueError("velocity arrows need velocities, and this trajectory kept positions only "
                             "(simulate(..., storage='positions')): render it without arrows, or simulate "
                             "with storage='float32'")
        base, name = settings.size, name or "trajectory"
        rate = keep_lesson_rate(video_fps(panels[0][1].fps, fps, quality), settings.min_fps, fps, quality, name)
        chapters = trajectory_chapters(panels, settings, settings.layout, rate)
        frames = chapters[0].frames
    frame_size = output_size(base, size, quality)
    if limits:
        check_limits(frame_size, frames)
    label = f"{frame_size[0]}x{frame_size[1]}" if size is not None else f"{frame_size[1]}p{rate:g}"
    return Plan(chapters, rate, frames, frame_size, name, label)


@dataclass
class Output:
    """Where and how a render is written, checked before anything is simulated: path, format,
    codec (the writer), frame (a single frame to write as PNG, or None), theme (the colours)."""
    path: Path
    format: str
    codec: str
    frame: int | None
    theme: object
    transparent: bool


def output_for(job: Plan, path, *, format=None, codec=None, transparent=False, background=None, theme=None,
               png_frame: int | None = None, last_frame: bool = False) -> Output:
    """The Output of a planned render to `path` (see render); ValueError for any mismatch. It
    writes nothing."""
    if last_frame and png_frame is not None:
        raise ValueError("choose one frame: the last (-s) or --png FRAME, not both")
    frame = job.frames - 1 if last_frame else png_frame
    if frame is not None and not 0 <= frame < job.frames:
        raise ValueError(f"frame {frame} is out of range: the video has frames 0..{job.frames - 1}")
    path, format = output_target(path, format, name=job.name, frame=frame is not None)
    codec = check_format(format, codec, transparent)
    colours = make_theme(theme, background)
    if frame is None:
        writer_for(codec)
        if format == "png":
            check_sequence_folder(path)
    return Output(path, format, codec, frame, colours, transparent)


def render(source, path, size=None, *, fps=None, quality=None, format=None, codec=None, transparent=False,
           background=None, theme=None, png_frame: int | None = None, last_frame: bool = False,
           limits: bool = True, settings: RenderSettings | None = None, progress=False,
           profile: dict | None = None) -> Path:
    """Render a Scene, a Trajectory, a list of (title, Trajectory), or a Plan from plan(), and
    return the path written.

    path: a file whose extension names the format (.mp4 .webm .gif .mov), a folder (a str
    ending in '/', or an existing directory) that receives <scene name>.<ext>, or with
    format='png' the folder of a PNG sequence. png_frame (or last_frame) writes that one frame
    as a PNG instead. quality: l, m, h, k (480p15, 720p30, 1080p60, 2160p60), also the encoder's
    quality; codec: h264 (default) or mp4v for mp4. transparent: background pixels get alpha 0
    (webm, mov, png). background: '#RRGGBB' or RGB, else the theme's; theme: dark or light, else
    the one whose text reads on the background (light on white), else dark.

    The output appears only when complete. `settings` draws trajectories (a scene brings its
    own). Bad input raises ValueError before anything is simulated. `progress`: a bar on stderr
    (True) or a render.video.Progress. `profile`, when given a dict, receives seconds per phase:
    simulation, draw and encode.
    """
    job = source if isinstance(source, Plan) else plan(source, size, fps=fps, quality=quality,
                                                         settings=settings, limits=limits)
    out = output_for(job, path, format=format, codec=codec, transparent=transparent, background=background,
                     theme=theme, png_frame=png_frame, last_frame=last_frame)
    if out.format == "gif" and out.frame is None and job.fps > GIF_MAX_FPS:
        warnings.warn(f"a GIF at {job.fps:g} fps plays slower in most browsers, which hold frames shorter "
                      f"than 2/100 s longer; {GIF_MAX_FPS} fps or less plays as made (--fps, or -ql)")
    created = check_writable(out.path.parent)
    try:
        with ctrl_c_safe():
            return play(job.chapters, job.fps, job.frames, out.path, job.size, codec=out.codec,
                        quality=quality or "m", png_frame=out.frame, transparent=transparent, theme=out.theme,
                        name=job.name, progress=progress, profile=profile)
    except BaseException:
        remove_empty_folders(created)   # a failed render leaves no folder it made either
        raise
