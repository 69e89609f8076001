"""A scene: what to simulate (a World, or several side by side), for how long, and how to draw it.

Scene files are Python files in scenes/ (manim's convention): the module docstring's first
line describes the scene, and a function `scene()` returns a `Scene`. They load by path
(`scenes/single_bounce.py`) or by name (`single_bounce`).
"""
from __future__ import annotations

import ast
import dataclasses
import importlib.util
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable, Optional

from .world import World

METHODS = ("discrete", "ccd")
QUALITY_SIZES = {"l": (854, 480), "m": (1280, 720), "h": (1920, 1080)}


@dataclass
class RenderSettings:
    """How a scene is drawn. `overlay(canvas, view, frame, trajectory)` draws scene-specific
    explanations (structures, captions) over a panel after the particles."""
    size: tuple = QUALITY_SIZES["m"]
    trails: int = 0            # motion-trail length in frames; 0 draws none
    arrows: bool = False       # velocity arrows
    arrow_seconds: float = 0.25  # an arrow shows where the particle would be this much later
    hud: bool = True
    flash: bool = True         # a brief ring at each impact
    overlay: Optional[Callable] = None
    layout: Optional[tuple] = None  # (rows, cols) of panels; by default up to three in a row


@dataclass
class Panel:
    """One titled simulation inside a scene drawn side by side with others."""
    scene: "Scene"
    title: str = ""


@dataclass
class Scene:
    """world + frame rate + duration + method + render settings.

    A scene made of `panels` shows several simulations side by side in one video; each panel
    keeps its own fps (a 15 fps panel in a 60 fps video holds each frame for 4 video frames).
    A scene made of `chapters` plays scenes one after another; `seconds` is the whole video
    (the last chapter's last frame holds if the chapters are shorter).
    """
    world: Optional[World] = None
    fps: float = 60.0
    seconds: float = 2.0
    method: str = "discrete"
    substeps: int = 1
    broadphase: str = "sweep_prune"
    name: str = "scene"
    description: str = ""
    render: RenderSettings = field(default_factory=RenderSettings)
    panels: tuple = ()
    chapters: tuple = ()

    def __post_init__(self):
        self.panels = tuple(self.panels)
        self.chapters = tuple(self.chapters)
        self.validate()

    @property
    def frames(self) -> int:
        """Frames in the video: fps × seconds."""
        return int(round(self.fps * self.seconds))

    def validate(self) -> None:
        _check_positive("fps", self.fps)
        _check_positive("seconds", self.seconds)
        if self.frames < 1:
            raise ValueError(f"seconds={self.seconds:g} at fps={self.fps:g} is shorter than one frame")
        if self.method not in METHODS:
            raise ValueError(f"unknown method '{self.method}'; choose one of: {', '.join(METHODS)}")
        if int(self.substeps) != self.substeps or self.substeps < 1:
            raise ValueError(f"substeps must be a whole number >= 1, got {self.substeps}")
        from .broadphase import METHODS as BROAD_PHASES
        if self.broadphase not in BROAD_PHASES:
            raise ValueError(f"unknown broad phase '{self.broadphase}'; choose one of: {', '.join(BROAD_PHASES)}")
        if sum((self.world is not None, bool(self.panels), bool(self.chapters))) != 1:
            raise ValueError("a scene needs exactly one of: a world, panels, chapters")

    def replace(self, **changes) -> "Scene":
        """A copy with some fields changed (and validated)."""
        return dataclasses.replace(self, **changes)

    def with_options(self, *, fps=None, seconds=None, method=None, substeps=None,
                     broadphase=None, restitution=None) -> "Scene":
        """Apply command-line style overrides. A panel scene keeps its panels' physics (they exist
        to compare settings); its video fps and duration change."""
        scene = self
        if fps is not None:
            scene = scene.replace(fps=fps)
        if seconds is not None:  # chapters keep their lengths: the video is cut or held
            panels = tuple(Panel(p.scene.replace(seconds=seconds), p.title) for p in scene.panels)
            scene = scene.replace(seconds=seconds, panels=panels)
        physics = {k: v for k, v in dict(method=method, substeps=substeps, broadphase=broadphase).items()
                   if v is not None}
        if scene.world is not None:
            if restitution is not None:
                world = scene.world.copy()
                world.restitution = float(restitution)
                world.validate()
                physics["world"] = world
            scene = scene.replace(**physics)
        return scene


def _check_positive(name: str, value) -> None:
    try:
        ok = float(value) > 0 and float(value) < float("inf")
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ValueError(f"{name} must be a finite number > 0, got {value}")


# --- loading scene files -------------------------------------------------------------------

def scene_dirs() -> list:
    """Where scenes are looked up by name: $COLLISIM_SCENES (os.pathsep-separated), ./scenes,
    and the scenes/ folder of the source tree this package belongs to."""
    dirs = [Path(p) for p in os.environ.get("COLLISIM_SCENES", "").split(os.pathsep) if p]
    dirs.append(Path.cwd() / "scenes")
    dirs.append(Path(__file__).resolve().parents[2] / "scenes")
    unique = []
    for d in dirs:
        if d.is_dir() and d.resolve() not in [u.resolve() for u in unique]:
            unique.append(d)
    return unique


def available_scenes() -> dict:
    """name -> path of every scene file that can be loaded by name (first folder wins)."""
    found = {}
    for folder in scene_dirs():
        for path in sorted(folder.glob("*.py")):
            if not path.name.startswith("_"):
                found.setdefault(path.stem, path)
    return found


def describe_scene_file(path: Path) -> str:
    """The first line of a scene file's docstring, read without running the file."""
    try:
        doc = ast.get_docstring(ast.parse(Path(path).read_text()))
    except (OSError, SyntaxError):
        doc = None
    return (doc or "").strip().splitlines()[0] if doc else ""


def resolve_scene_path(name_or_path) -> Path:
    text = str(name_or_path)
    path = Path(text)
    if text.endswith(".py") or os.sep in text:
        if not path.is_file():
            raise ValueError(f"scene file not found: {text}")
        return path
    scenes = available_scenes()
    if text not in scenes:
        known = ", ".join(sorted(scenes)) or "none found"
        raise ValueError(f"unknown scene '{text}'; available: {known}")
    return scenes[text]


def load_scene(name_or_path) -> Scene:
    """Load a scene by name (`single_bounce`) or by path (`scenes/single_bounce.py`)."""
    path = resolve_scene_path(name_or_path)
    module_name = f"collisim_scene_{path.stem}"
    spec = importlib.util.spec_from_file_location(module_name, path)
    module = importlib.util.module_from_spec(spec)
    try:
        spec.loader.exec_module(module)
        build = getattr(module, "scene", None)
        if not callable(build):
            raise ValueError(f"scene file {path} defines no function scene()")
        scene = build()
    except ValueError as error:
        raise ValueError(f"scene {path.stem}: {error}") from None
    except Exception as error:  # a scene file is user code: report it in one line
        raise ValueError(f"scene file {path} raised {type(error).__name__}: {error}") from None
    finally:
        sys.modules.pop(module_name, None)
    if not isinstance(scene, Scene):
        raise ValueError(f"scene file {path}: scene() returned {type(scene).__name__}, not a Scene")
    description = scene.description or describe_scene_file(path)
    return scene.replace(name=path.stem, description=description)
