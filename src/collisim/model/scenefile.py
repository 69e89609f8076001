"""Scene files: Python files in scenes/ (manim's convention) whose module docstring's first
line describes the scene and whose function `scene()` returns a Scene. They load by path
(`scenes/single_bounce.py`) or by name (`single_bounce`), looked up in $COLLISIM_SCENES
(os.pathsep-separated folders), ./scenes, and the scenes/ folder of this source tree.
"""
from __future__ import annotations

import ast
import importlib.util
import os
import sys
from pathlib import Path

from .scene import Scene
from ..core.checks import is_file, missing_file


def scene_dirs() -> list:
    """Where scenes are looked up by name: $COLLISIM_SCENES (os.pathsep-separated), ./scenes,
    and the scenes/ folder of the source tree this package belongs to."""
    dirs = [Path(p) for p in os.environ.get("COLLISIM_SCENES", "").split(os.pathsep) if p]
    dirs.append(Path.cwd() / "scenes")
    dirs.append(Path(__file__).resolve().parents[3] / "scenes")
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
    if path.suffix not in ("", ".py") and is_file(path):   # another kind of file: not "unknown scene"
        raise ValueError(f"{text} is not a scene file: scene files are Python, ending in .py")
    if text.endswith(".py") or os.sep in text:
        if not is_file(path):
            raise ValueError(missing_file("scene file", text))
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
