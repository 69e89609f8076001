"""Videos in Jupyter: `show(source)` renders a Scene or a Trajectory to an H.264 MP4 and returns
an object that a notebook displays as a looping `<video>`; `trajectory_preview_html` is the
short preview a Trajectory shows of itself.

    show(scene) -> collisim.render(...) -> MP4 -> Video (._repr_html_: <video>, .path)

A Trajectory shows that preview through `Trajectory.preview_html`, which this module sets: the
model sits below the pipeline that makes videos, and does not import it.
"""
from __future__ import annotations

import base64
import dataclasses
import html
import os
import shutil
import tempfile
from pathlib import Path

import numpy as np

from .core.checks import number
from .model.scene import Scene
from .model.trajectory import _FRAME_FIELDS, Trajectory, load_trajectory
from .pipeline import render

PREVIEW_SIZE = (320, 180)    # a Trajectory's own preview: small ...
PREVIEW_SECONDS = 5.0        # ... and short, since Jupyter renders it for every displayed run
LINKED_FOLDER = "renders"    # embed=False writes here, under the notebook's working folder


class Video:
    """A rendered MP4 that Jupyter displays as `<video controls autoplay loop muted>`.

    path: the MP4 file
    embedded: True when the HTML carries the whole video as a base64 data URI; otherwise its
              `src` is `path` relative to the working folder (the notebook's, in Jupyter)
    """

    def __init__(self, path, embedded: bool):
        self.path = Path(path)
        self.embedded = bool(embedded)
        self._src = _data_uri(self.path) if self.embedded else _relative_link(self.path)

    def _repr_html_(self) -> str:
        # no width or height: the video shows at its own size, shrunk to fit a narrow cell
        return (f'<video controls autoplay loop muted playsinline style="max-width: 100%" '
                f'src="{html.escape(self._src, quote=True)}"></video>')

    def __repr__(self) -> str:
        return f"Video({str(self.path)!r}, {'embedded' if self.embedded else 'linked'})"


def show(source, *, size=(640, 360), seconds=None, embed: bool = True, settings=None) -> Video:
    """Render `source` to an H.264 MP4 and return a Video, which a notebook cell displays.

    source: a Scene, a Trajectory, or the path (str or os.PathLike) of a trajectory saved with
            Trajectory.save (.npz)
    size: (width, height) of the video in pixels (None: the scene's or the settings' own)
    seconds: play only this much (a Scene is simulated for this long; a Trajectory is cut to
             its first `seconds`); None plays it all
    embed: True writes the MP4 to a new temporary folder and embeds it in the notebook as a
           base64 data URI (the notebook file then carries the video); False writes it to
           renders/<name>.mp4 under the working folder (the notebook's) and links it there
    settings: a RenderSettings that draws a Trajectory (a Scene brings its own), as in
              collisim.render

    Bad input (an unknown source type, a file that is not a trajectory, seconds <= 0, a size
    that is too small) raises ValueError with one line.
    """
    if isinstance(source, (str, os.PathLike)):
        name, source = Path(source).stem, load_trajectory(source)
    elif isinstance(source, Scene):
        name = source.name
    elif isinstance(source, Trajectory):
        name = "trajectory"
    else:
        raise ValueError("show takes a Scene, a Trajectory or the path of a saved trajectory (.npz), "
                         f"not {type(source).__name__}")
    if seconds is not None:
        source = source.with_options(seconds=seconds) if isinstance(source, Scene) else first_seconds(source, seconds)
    if not embed:
        path = render(source, Path.cwd() / LINKED_FOLDER / f"{name}.mp4", size, settings=settings, codec="h264")
        return Video(path, embedded=False)
    folder = Path(tempfile.mkdtemp(prefix="collisim-show-"))  # kept (the OS clears it) so .path stays valid
    try:
        path = render(source, folder / f"{name}.mp4", size, settings=settings, codec="h264")
    except BaseException:
        shutil.rmtree(folder, ignore_errors=True)
        raise
    return Video(path, embedded=True)


def trajectory_preview_html(traj) -> str:
    """The HTML a Trajectory shows in Jupyter: its first PREVIEW_SECONDS at PREVIEW_SIZE,
    embedded. Meant as `Trajectory._repr_html_`. The HTML carries the whole video, so its
    temporary folder goes at once: Jupyter makes a preview for every run a cell displays."""
    video = show(traj, size=PREVIEW_SIZE, seconds=PREVIEW_SECONDS, embed=True)
    shutil.rmtree(video.path.parent, ignore_errors=True)
    return video._repr_html_()


def first_seconds(traj, seconds: float):
    """The Trajectory cut to its samples at times <= seconds (at least one frame), with the
    events of that span. A trajectory shorter than `seconds` is returned whole."""
    seconds = number("seconds", seconds, positive=True)
    frames = max(1, int(round(seconds * traj.fps)))
    if frames >= traj.frames:
        return traj
    cut = {name: getattr(traj, name)[:frames + 1] for name in _FRAME_FIELDS}
    events = traj.events.take(np.flatnonzero(traj.events.time <= traj.times[frames]))
    return dataclasses.replace(traj, **cut, events=events)


def _data_uri(path: Path) -> str:
    return "data:video/mp4;base64," + base64.b64encode(path.read_bytes()).decode("ascii")


def _relative_link(path: Path) -> str:
    """`path` relative to the working folder, in URL form, with the file's modification time as a
    query so that a browser shows a re-rendered video instead of its cached copy."""
    relative = Path(os.path.relpath(path, Path.cwd())).as_posix()
    return f"{relative}?v={path.stat().st_mtime_ns}"


Trajectory.preview_html = trajectory_preview_html
