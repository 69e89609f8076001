"""The explainer's items (render/explain.py draws them): captions, arrows, marks, notes and
figures, each checked when it is made, so that a mistake is one line before anything renders.

Times are seconds of the panel's clock, None (never), or functions of the frame's state;
points are world points or functions of the state.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable, Optional, Union

import numpy as np

from ..core.checks import is_whole

Point = Union[tuple, np.ndarray, Callable]
STRIP_NAMES = ("top", "bottom")
PLACES = ("side", "top", "bottom", "box")


def _check_times(item) -> None:
    """An item's start and end: seconds (not NaN), None (never), or functions of the state."""
    for name in ("start", "end"):
        value = getattr(item, name)
        if value is not None and not callable(value) and (isinstance(value, bool) or
                                                          not isinstance(value, (int, float, np.number))
                                                          or math.isnan(value)):
            raise ValueError(f"{type(item).__name__} {name} must be seconds, None or a function of the state, "
                             f"got {value!r}")


def check_choice(item, name: str, choices: tuple) -> None:
    if getattr(item, name) not in choices:
        raise ValueError(f"{type(item).__name__} {name} must be one of {', '.join(map(repr, choices))}, "
                         f"got {getattr(item, name)!r}")


@dataclass
class Caption:
    text: Union[str, Callable]
    start: float = 0.0
    end: float = math.inf
    strip: str = "bottom"        # "top" or "bottom"
    line: int = 0                # 0 is the strip's first line

    def __post_init__(self):
        _check_times(self)
        check_choice(self, "strip", STRIP_NAMES)
        if not is_whole(self.line):
            raise ValueError(f"Caption line must be a whole number >= 0, got {self.line!r}")


@dataclass
class Arrow:
    tail: Point
    head: Point
    start: float = 0.0
    end: float = math.inf
    label: str = ""
    color: Optional[tuple] = None
    label_gap: float = 0.0       # world units between the head and its label, to the right

    def __post_init__(self):
        _check_times(self)


@dataclass
class Mark:
    bodies: tuple
    start: float = 0.0
    end: float = math.inf
    labels: Optional[tuple] = None   # default: 1, 2, 3, ... in the order given

    def __post_init__(self):
        _check_times(self)
        self.bodies = tuple(self.bodies)
        if not self.bodies or not all(is_whole(b) for b in self.bodies):
            raise ValueError(f"Mark bodies must be body numbers >= 0, got {self.bodies!r}")


@dataclass
class Note:
    text: Union[str, Callable]   # or a function of the state; "" or None from it: not drawn
    at: Point
    start: float = 0.0
    end: float = math.inf
    gap: float = 0.0             # world units between the point and the text, to its right

    def __post_init__(self):
        _check_times(self)


@dataclass
class Figure:
    draw: Callable                 # draw(canvas, rect, view, state, unit): within rect (x, y, w, h)
    start: float = 0.0
    end: float = math.inf
    place: str = "side"            # "side", "top", "bottom" or "box"

    def __post_init__(self):
        _check_times(self)
        check_choice(self, "place", PLACES)
