"""A scene: what to simulate (a World, or several side by side), for how long, and how to draw
it. Scene files that build one are loaded by scenefile.py."""
from __future__ import annotations

import dataclasses
import warnings
from dataclasses import dataclass, field
from typing import Callable, Optional

from ..core import checks
from ..palette import parse_colors
from .world import World

QUALITY_SIZES = {"l": (854, 480), "m": (1280, 720), "h": (1920, 1080)}


@dataclass
class RenderSettings:
    """How a scene is drawn.

    `overlay(canvas, view, state)` draws scene-specific explanations (structures, captions)
    over a panel after the bodies: canvas is the (height, width, 3) uint8 BGR frame, view maps
    world to pixels (render/view.py), state is the panel's render.player.FrameState (time,
    sample, positions, velocities, angles, the sample's collision counts, and the running
    `counters` below).
    `counters` maps a name to `count(before, after)`, called for every pair of consecutive
    samples (FrameState) the panel plays; the player keeps the running sum in
    state.counters[name], so an overlay can show a number that derives from the trajectory
    (such as missed collisions) without simulating anything.
    `colors`: one colour per body, '#RRGGBB' or (r, g, b) in 0..255, drawing the bodies (and
    their trails) in place of the World's colours (by default one per size, so a rack of equal
    balls is one colour); its length must be the number of bodies.
    `min_fps`: the video frame rate what the scene teaches needs (frame_rate's 60 fps panel must
    move more smoothly than its 15 fps one): a quality preset (-ql's 15 fps) lowers the size but
    keeps at least this rate, and says so; an explicit fps is the user's."""
    size: tuple = QUALITY_SIZES["m"]
    trails: int = 0            # motion-trail length in frames; 0 draws none
    arrows: bool = False       # velocity arrows
    arrow_seconds: float = 0.25  # an arrow shows where the particle would be this much later
    hud: bool = True
    flash: bool = True         # a brief ring at each impact
    overlay: Optional[Callable] = None
    layout: Optional[tuple] = None  # (rows, cols) of panels; by default up to three in a row
    counters: dict = field(default_factory=dict)
    explainer: Optional[object] = None   # render.explain.Explainer: captions, formulas, arrows, marks
    pace: Optional[object] = None        # render.pace.Pace: slow motion and freeze frames
    min_fps: Optional[float] = None      # the lowest video frame rate the lesson survives
    colors: Optional[object] = None      # one colour per body, in place of the World's

    def __post_init__(self):
        """Refuse, in one line, what the player could only fail on mid-render (colors of the
        wrong length are refused when the scene is planned: check_colors)."""
        self.size = checks.whole_pair("size", self.size)
        self.layout = None if self.layout is None else checks.whole_pair("layout", self.layout)
        if not checks.is_whole(self.trails):
            raise ValueError(f"trails must be a whole number of frames >= 0, got {self.trails!r}")
        self.arrow_seconds = checks.number("arrow_seconds", self.arrow_seconds, positive=True)
        if self.overlay is not None and not callable(self.overlay):
            raise ValueError(f"overlay must be a function overlay(canvas, view, state), got {self.overlay!r}")
        if not isinstance(self.counters, dict) or not all(callable(c) for c in self.counters.values()):
            raise ValueError("counters must map names to functions count(before, after), got "
                             f"{self.counters!r}")
        if self.explainer is not None and not (hasattr(self.explainer, "draw") and hasattr(self.explainer, "strips")):
            raise ValueError(f"explainer must be an Explainer (collisim.render.explain), got {self.explainer!r}")
        if self.pace is not None and not hasattr(self.pace, "simulation_time"):
            raise ValueError(f"pace must be a Pace (collisim.render.pace), got {self.pace!r}")
        if self.colors is not None:
            self.colors = parse_colors(self.colors)
        if self.min_fps is not None:
            self.min_fps = checks.number("min_fps", self.min_fps, positive=True)


    def check_colors(self, bodies: int) -> None:
        """ValueError unless colors, when given, has one colour per body."""
        if self.colors is not None and len(self.colors) != bodies:
            raise ValueError(f"colors has {len(self.colors)} colours, and the world has {bodies} bodies: give one "
                             f"colour per body")


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
    broadphase: str = "auto"
    # the contact model: below rest_speed a body falls asleep (ccd: held still by what it
    # touches, engine/ccd/sleep.py; discrete: its whole island still for half a second,
    # engine/islands.py; None: the speed of a bounce a thousandth of its radius high under
    # gravity when e < 1, else never; 0: never); for ccd, a collision within tc seconds of a
    # body's last one is elastic (Luding and McNamara's TC model; None: a hundredth of the time
    # gravity takes to reach the rest speed, 0 where nothing sleeps; 0: off)
    rest_speed: Optional[float] = None
    tc: Optional[float] = None
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
        """Check (and normalise) the fields; ValueError with one line for anything wrong."""
        self.fps = checks.number("fps", self.fps, positive=True)
        self.seconds = checks.number("seconds", self.seconds, positive=True)
        if self.frames < 1:
            raise ValueError(f"seconds={self.seconds:g} at fps={self.fps:g} is shorter than one frame")
        if abs(self.frames - self.fps * self.seconds) > 1e-9 * self.frames:
            warnings.warn(f"{self.seconds:g} s at {self.fps:g} fps is {self.fps * self.seconds:g} frames; "
                          f"using {self.frames} frames ({self.frames / self.fps:g} s)", stacklevel=4)
        if not checks.is_whole(self.substeps, 1):
            raise ValueError(f"substeps must be a whole number >= 1, got {self.substeps!r}")
        self.substeps = int(self.substeps)
        if self.rest_speed is not None:
            self.rest_speed = checks.number("rest_speed", self.rest_speed, low=0.0)
        if self.tc is not None:
            self.tc = checks.number("tc", self.tc, low=0.0)
        if sum((self.world is not None, bool(self.panels), bool(self.chapters))) != 1:
            raise ValueError("a scene needs exactly one of: a world, panels, chapters")

    def replace(self, **changes) -> "Scene":
        """A copy with some fields changed (and validated)."""
        return dataclasses.replace(self, **changes)

    def with_options(self, *, fps=None, seconds=None, method=None, substeps=None,
                     broadphase=None, restitution=None) -> "Scene":
        """Apply command-line style overrides. A panel scene keeps its panels' physics (they exist
        to compare settings); its video fps and duration change."""
        timing = {}   # fps and seconds in one step: an error names the values asked for together
        if fps is not None:
            timing["fps"] = fps
        if seconds is not None:  # chapters keep their lengths: the video is cut or held
            timing["seconds"] = seconds
            timing["panels"] = tuple(Panel(p.scene.replace(seconds=seconds), p.title) for p in self.panels)
        scene = self.replace(**timing) if timing else self
        physics = {k: v for k, v in dict(method=method, substeps=substeps, broadphase=broadphase).items()
                   if v is not None}
        if scene.world is not None:
            if restitution is not None:
                physics["world"] = scene.world.copy(restitution=float(restitution))
            scene = scene.replace(**physics)
        return scene
