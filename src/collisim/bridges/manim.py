"""A collisim Trajectory as a manim (Community Edition) Mobject that plays itself.

    from collisim.bridges.manim import TrajectoryMobject

    class Collision(manim.Scene):
        def construct(self):
            self.add(TrajectoryMobject(collisim.simulate(collisim.load_scene("two_bodies"))))
            self.wait(5)

The Mobject keeps its own clock: an updater advances it by manim's dt (times playback_rate)
and places every body at the trajectory's state interpolated linearly between the two samples
around that time, so playback speed does not depend on the scene's frame rate. At the end of
the trajectory it holds the last state. Each body is drawn as its shape in the world's colours
(a manim Circle, or a Polygon of its vertices, turned with the body), the box as a Rectangle,
the segments as Lines and a collision map as its outlines (closed polygons); world units map to
manim units by one scale and offset (`width`, `center`), read back from the box's outline each
frame, so the whole group can be moved or scaled like any other Mobject.

This module needs manim (the `manim` extra); `import collisim` never imports it.
"""
from __future__ import annotations

import numpy as np

try:
    import manim
except ModuleNotFoundError as error:
    if error.name != "manim":  # manim is there but something it needs is not: show the real cause
        raise
    raise ImportError("the manim bridge needs the manim extra: pip install 'collisim[manim]'") from None

from .. import palette
from ..core.geometry.polygon import polygon_mass_properties
from ..model.trajectory import Trajectory

FRAME_FILL = 0.9  # by default the box spans this fraction of the frame's width or height


def hex_color(rgb) -> str:
    """'#rrggbb' for an RGB triple of 0..255 integers (manim accepts hex on every version)."""
    r, g, b = (int(c) for c in rgb)
    return f"#{r:02x}{g:02x}{b:02x}"


def default_width(box) -> float:
    """The largest width (manim units) at which the box (xmin, ymin, xmax, ymax) fits in
    FRAME_FILL of the current manim frame."""
    box_width, box_height = box[2] - box[0], box[3] - box[1]
    scale = FRAME_FILL * min(manim.config.frame_width / box_width, manim.config.frame_height / box_height)
    return scale * box_width


class TrajectoryMobject(manim.VGroup):
    """A VGroup of the box (a Rectangle), the statics (segments as Lines, a collision map's
    outlines as Polygons) and the bodies (Circles and Polygons) of a Trajectory, playing it on its
    own clock.

    trajectory: a collisim Trajectory (positions (F, n, 2), angles (F, n), times (F,))
    width: manim units the box spans horizontally (None: the largest that fits the frame)
    center: the manim point (2 or 3 coordinates) where the box's centre goes
    playback_rate: trajectory seconds per scene second (2.0 plays twice as fast)
    Other keyword arguments go to manim.VGroup.

    Attributes: `time` (trajectory seconds played, from 0 to `end_time`), `outline`,
    `segment_lines`, `map_outlines` (empty without a map), `bodies` (one Circle or Polygon per
    body, in body order). `seek(t)` places the bodies at trajectory time t; `to_manim(points)`
    maps world points (k, 2) to manim points (k, 3).
    """

    def __init__(self, trajectory: Trajectory, *, width: float | None = None, center=manim.ORIGIN,
                 playback_rate: float = 1.0, **kwargs):
        if not isinstance(trajectory, Trajectory):
            raise ValueError(f"TrajectoryMobject takes a collisim Trajectory, not {type(trajectory).__name__}")
        _check_positive("playback_rate", playback_rate)
        world = trajectory.world
        box = np.asarray(world.box, dtype=np.float64)
        width = default_width(box) if width is None else _check_positive("width", width)
        center = _manim_point(center)
        scale = width / (box[2] - box[0])
        super().__init__(**kwargs)
        self.trajectory = trajectory
        self.playback_rate = float(playback_rate)
        self.time = 0.0
        self._world_box = box
        self.outline = manim.Rectangle(width=width, height=scale * (box[3] - box[1]),
                                       color=hex_color(palette.BOX), stroke_width=2).move_to(center)
        self.segment_lines = manim.VGroup(*(
            manim.Line(*self.to_manim(np.reshape(segment, (2, 2))), color=hex_color(palette.BOX), stroke_width=3)
            for segment in world.segments))
        chains = [] if world.map is None else world.map.chains
        self.map_outlines = manim.VGroup(*(
            manim.Polygon(*self.to_manim(chain), color=hex_color(palette.BOX), stroke_width=2) for chain in chains))
        self.bodies = manim.VGroup(*(_body_shape(world, i, scale) for i in range(world.n)))
        self._drawn_angles = np.zeros(world.n)  # the angle each body is turned to now
        self.add(self.outline, self.map_outlines, self.segment_lines, self.bodies)
        self.seek(0.0)
        self.add_updater(self._advance)

    @property
    def end_time(self) -> float:
        """The trajectory's last sample time: the clock stops there."""
        return float(self.trajectory.times[-1])

    @property
    def world_scale(self) -> float:
        """Manim units per world unit, as the box is drawn now."""
        return self.outline.width / (self._world_box[2] - self._world_box[0])

    def to_manim(self, points) -> np.ndarray:
        """World points (k, 2) -> manim points (k, 3) (z = 0), as the box is drawn now.

        The mapping is read from the outline rather than stored, so it follows the group when it
        is shifted or scaled."""
        points = np.atleast_2d(np.asarray(points, dtype=np.float64))
        box_centre = 0.5 * (self._world_box[:2] + self._world_box[2:])
        xy = self.outline.get_center()[:2] + self.world_scale * (points - box_centre)
        return np.column_stack([xy, np.zeros(len(xy))])

    def state_at(self, t: float) -> tuple:
        """The trajectory's positions (n, 2) and angles (n,) at time t, linear between the two
        samples around t; before the first sample the first, after the last the last."""
        times = self.trajectory.times
        if len(times) == 1 or t <= times[0]:
            return self.trajectory.positions[0], self.trajectory.angles[0]
        if t >= times[-1]:
            return self.trajectory.positions[-1], self.trajectory.angles[-1]
        k = int(np.searchsorted(times, t, side="right")) - 1  # times[k] <= t < times[k + 1]
        w = (t - times[k]) / (times[k + 1] - times[k])
        positions = (1.0 - w) * self.trajectory.positions[k] + w * self.trajectory.positions[k + 1]
        angles = (1.0 - w) * self.trajectory.angles[k] + w * self.trajectory.angles[k + 1]
        return positions, angles

    def seek(self, t: float) -> "TrajectoryMobject":
        """Set the clock to t (clamped to 0..end_time) and draw the bodies there."""
        self.time = min(max(float(t), 0.0), self.end_time)
        positions, angles = self.state_at(self.time)
        centres = self.to_manim(positions)
        for i, body in enumerate(self.bodies):
            body.shift(centres[i] - body_centre(body))
            turn = angles[i] - self._drawn_angles[i]
            if turn != 0.0:  # a circle looks the same turned, but a user may have added a marker to it
                body.rotate(turn, about_point=centres[i])
                self._drawn_angles[i] = angles[i]
        return self

    def _advance(self, mobject, dt: float) -> None:
        """The updater: manim calls it once per frame with the frame's dt in scene seconds."""
        self.seek(self.time + dt * self.playback_rate)


def _body_shape(world, i: int, scale: float):
    """Body i at angle 0 about the manim origin, `scale` manim units per world unit: a Circle of
    its radius, or a Polygon of its vertices about its centroid."""
    style = dict(color=hex_color(world.colors[i]), fill_opacity=1.0, stroke_width=0)
    vertices = world.body_vertices[world.vertex_start[i]:world.vertex_start[i + 1]]
    if len(vertices) == 0:
        return manim.Circle(radius=scale * world.radii[i], **style)
    return manim.Polygon(*np.column_stack([scale * vertices, np.zeros(len(vertices))]), **style)


def body_centre(body) -> np.ndarray:
    """The manim point (3,) a body's trajectory position maps to: a Circle's centre, a Polygon's
    centroid (the point it turns about; its bounding box's centre, manim's get_center, is not).
    Read from the shape as drawn, so it follows the group when it is moved or scaled."""
    if isinstance(body, manim.Circle):
        return body.get_center()
    corners = body.get_vertices()
    _, centroid, _ = polygon_mass_properties(corners[:, :2])
    return np.array([centroid[0], centroid[1], corners[0, 2]])


def _check_positive(name: str, value) -> float:
    try:
        value = float(value)
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be a finite number > 0, got {value}") from None
    if not 0.0 < value < float("inf"):
        raise ValueError(f"{name} must be a finite number > 0, got {value}")
    return value


def _manim_point(point) -> np.ndarray:
    """A manim point (3,) from 2 or 3 coordinates."""
    point = np.asarray(point, dtype=np.float64).ravel()
    if point.size not in (2, 3) or not np.all(np.isfinite(point)):
        raise ValueError(f"center must be 2 or 3 finite coordinates, got {point.tolist()}")
    return np.concatenate([point, np.zeros(3 - point.size)])
