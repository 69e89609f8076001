"""The world: bodies (each with a pose, a velocity, a mass and a shape) and statics (the box
walls and thin segments), as a structure of numpy arrays.

Every per-body quantity is one array with the body index first, so the compiled kernels walk
them with plain loops and numpy acts on all bodies at once. World units are math units: y
points up, angles are counter-clockwise radians.
"""
from __future__ import annotations

import numpy as np

from ..palette import default_colors
from ..core import checks
from ..core.geometry.polygon import place_polygons
from .bodyshapes import polygons_of, shape_table
from ..core.kinds import CAPSULE, CIRCLE, POLYGON


class World:
    """n bodies in an axis-aligned box, with constant accelerations.

    Bodies:
    positions: (n, 2)            centres of mass
    velocities: (n, 2)
    angles: (n,)                 orientation (a circle's shows only in how it is drawn)
    angular_velocities: (n,)
    accelerations: (n, 2)        constant; by default every body gets `gravity`
    radii: (n,)                  > 0 (a scalar is broadcast): the circle's radius; for a polygon,
                                 its bounding circle's (set from the polygon)
    masses: (n,)                 > 0; by default proportional to area (density 1)
    inertias: (n,)               moment of inertia about the centre of mass, from the shape
                                 (½·m·r² for a disc)
    shapes: (n,) int8            shape kind of each body (kinds.CIRCLE, POLYGON, CAPSULE)
    shapes= (the argument; polygons= is the same): None, or n entries: None (a circle), a
                                 shapes.capsule(length, radius), or a polygon's vertices (k, 2)
                                 in the body frame, kept about the centroid (model/bodyshapes.py)
    vertex_start (n + 1,), body_vertices (V, 2): every polygon's vertices about its centroid,
                                 and every capsule's two cap centres (±length/2, 0)
    capsule_radii: (n,)          each capsule's own radius (NaN for other bodies)
    friction: μ >= 0 for every contact (Coulomb; 0 = frictionless)
    colors: (n, 3) uint8         RGB; by default one colour per size class
    Statics:
    box: (xmin, ymin, xmax, ymax)  the walls
    segments: (m, 4)             thin segments x0, y0, x1, y1 with no thickness
    map: a CollisionMap or None  a level made from an image (statics/collision_map.py)
    restitution: e in [0, 1] for every contact (1 = elastic)
    damping: d in [0, 1], the fraction of its velocity (linear and angular) a body keeps after
                                 one second of free motion, as pymunk's Space.damping (1 = none);
                                 the discrete method applies d**dt every step, ccd does not model it
    """

    def __init__(self, positions, velocities=None, radii=1.0, masses=None, *,
                 box=(0.0, 0.0, 10.0, 10.0), gravity=(0.0, 0.0), accelerations=None,
                 colors=None, restitution: float = 1.0, segments=None, angles=0.0,
                 angular_velocities=0.0, map=None, polygons=None, friction: float = 0.0, damping: float = 1.0,
                 shapes=None):
        self.positions = checks.positions_array(positions)
        n = len(self.positions)
        if shapes is not None and polygons is not None:
            raise ValueError("give the bodies' shapes once: shapes= or polygons= (the same argument), not both")
        table = shape_table(polygons if shapes is None else shapes, n)
        self.velocities = checks.per_body("velocities", 0.0 if velocities is None else velocities, n, 2)
        self.angles = checks.per_body("angles", 0.0 if angles is None else angles, n)
        self.angular_velocities = checks.per_body("angular_velocities",
                                                    0.0 if angular_velocities is None else angular_velocities, n)
        self.gravity = checks.vector("gravity", gravity, "(0, -9.81)")
        self.accelerations = checks.per_body("accelerations", self.gravity if accelerations is None
                                               else accelerations, n, 2)
        self.radii = checks.per_body("radii", radii, n)
        # the shapes whose size the table gives (a capsule's radius there is its bounding circle's)
        polygon = (table.shapes == POLYGON) | (table.shapes == CAPSULE)
        self.radii = np.where(polygon, table.radii, self.radii)
        self.positions = self.positions + _rotated(table.offsets, self.angles)   # to the centroids
        areas = np.where(polygon, table.areas, np.pi * self.radii ** 2)
        self.masses = checks.per_body("masses", areas if masses is None else masses, n)
        if masses is None and np.any((self.masses == 0) & (self.radii > 0)):
            i = int(np.flatnonzero((self.masses == 0) & (self.radii > 0))[0])
            raise ValueError(f"radius {self.radii[i]:g} of body {i} is too small: its area is 0 in floating point")
        self.shapes, self.vertex_start, self.body_vertices = table.shapes, table.start, table.vertices
        self.capsule_radii = table.capsule_radii
        self._inertia_per_mass = np.where(polygon, table.second_moments / np.where(polygon, table.areas, 1.0),
                                          0.5 * self.radii ** 2)
        self.notes = list(table.notes)
        self.friction = checks.number("friction", friction, low=0.0)
        self.box = checks.per_body("box", box, 4)
        self.segments = checks.segments_array(segments)
        self.map = checks.collision_map(map)
        if restitution is None:
            raise ValueError("restitution must be a number in [0, 1], got None")
        self.restitution = checks.number("restitution", restitution, low=0.0, high=1.0)
        self.damping = checks.number("damping", damping, low=0.0, high=1.0)
        self.colors = default_colors(self.radii) if colors is None else np.array(colors, dtype=np.uint8).reshape(n, 3)
        self.validate()

    @property
    def n(self) -> int:
        return len(self.positions)

    @property
    def inertias(self) -> np.ndarray:
        """(n,) moments of inertia about the centres of mass: ½·m·r² for a solid disc, the
        polygon's own for a polygon (uniform density)."""
        return self.masses * self._inertia_per_mass

    def placed_vertices(self, positions=None, angles=None) -> np.ndarray:
        """Every polygon's vertices (V, 2) in the world, at the bodies' own poses unless given
        (positions (n, 2), angles (n,)); body i's are rows vertex_start[i]:vertex_start[i + 1]."""
        if len(self.body_vertices) == 0:   # circles alone: nothing to place (and no kernel to compile)
            return np.empty_like(self.body_vertices)
        positions = self.positions if positions is None else np.ascontiguousarray(positions, np.float64)
        angles = self.angles if angles is None else np.ascontiguousarray(angles, np.float64)
        return place_polygons(self.body_vertices, self.vertex_start, positions, angles,
                              np.empty_like(self.body_vertices))

    def world_vertices(self, i: int) -> np.ndarray:
        """Polygon body i's vertices (k, 2) in the world, at its own pose."""
        return self.placed_vertices()[self.vertex_start[i]:self.vertex_start[i + 1]]

    def extents(self) -> tuple[np.ndarray, np.ndarray]:
        """Each body's axis-aligned bounds (n, 2) lo, hi at its pose: centre ± radius for a
        circle, its vertices' for a polygon, its cap centres' ± its radius for a capsule."""
        r = self.radii[:, None]
        lo, hi = self.positions - r, self.positions + r
        shaped = np.flatnonzero(self.shapes != CIRCLE)   # a polygon's or capsule's rows of the vertex table
        if shaped.size:
            corners, starts = self.placed_vertices(), self.vertex_start[shaped]
            round_by = np.where(self.shapes[shaped] == CAPSULE, self.capsule_radii[shaped], 0.0)[:, None]
            lo[shaped] = np.minimum.reduceat(corners, starts, axis=0) - round_by
            hi[shaped] = np.maximum.reduceat(corners, starts, axis=0) + round_by
        return lo, hi

    @property
    def polygons(self) -> list | None:
        """Each body's shape as World's `shapes` argument takes it: None for a circle, its
        shapes.Capsule, or its polygon about its centroid; None if all are circles."""
        return polygons_of(self.vertex_start, self.body_vertices, self.capsule_radii)

    @property
    def level_segments(self) -> np.ndarray:
        """(m + k, 4) the world's segments, then the collision map's contour chains: the exact
        outline of the level (ccd and the pymunk reference collide with it; the discrete method
        samples the map's distance field instead)."""
        if self.map is None:
            return self.segments
        return np.concatenate([self.segments, self.map.segments])

    @property
    def uniform_acceleration(self) -> bool:
        """True when every body has the same constant acceleration."""
        return self.n == 0 or bool(np.all(self.accelerations == self.accelerations[0]))

    def validate(self) -> None:
        """Raise ValueError with one clear line for any state the engine cannot run (core/checks.py);
        overlaps between bodies and statics are checked where the engine starts (engine/start.py)."""
        xmin, ymin, xmax, ymax = self.box
        if not (xmax > xmin and ymax > ymin):
            raise ValueError(f"box must have xmax > xmin and ymax > ymin, got {self.box.tolist()}")
        for name, values in (("radius", self.radii), ("mass", self.masses)):
            bad = np.flatnonzero(values <= 0)
            if bad.size:
                raise ValueError(f"{name} must be > 0 (particle {bad[0]} has {name} {values[bad[0]]:g})")
        lo, hi = self.extents()
        too_big = np.flatnonzero(np.any(hi - lo > self.box[2:] - self.box[:2], axis=1))
        if too_big.size:
            raise ValueError(f"{self._named(too_big[0])} is larger than the box")
        self._moves_where_it_fits(lo, hi)
        outside = np.any((lo < self.box[:2]) | (hi > self.box[2:]), axis=1)
        if outside.any():
            i = np.flatnonzero(outside)[0]
            x, y = self.positions[i]
            where = f"reaches {self._beyond(i, lo[i], hi[i])}"
            raise ValueError(f"{self._named(i)} at ({x:g}, {y:g}) {where}")
        if np.any(self.shapes == POLYGON) and self.map is not None:
            raise ValueError("polygon bodies meet the box walls, segments and each other; collision maps "
                             "collide with circles only: leave the map out of a world with polygons")
        if np.any(self.shapes == CAPSULE) and self.map is not None:
            raise ValueError("capsules meet the box walls, segments and every other body; collision maps "
                             "collide with circles only: leave the map out of a world with capsules")

    def _moves_where_it_fits(self, lo, hi) -> None:
        """ValueError for a body as wide (or as tall) as the box that moves across it: pressed
        between two walls at once, it has no room to move, and a velocity it has there cannot be
        kept (ccd would bounce it between the walls for ever at one instant, and the discrete
        step would drop it). With any room left it bounces between the walls, however often."""
        fills = self.box[2:] - self.box[:2] - (hi - lo) <= 0.0
        across = np.argwhere(fills & (self.velocities != 0.0))
        if across.size:
            i, axis = across[0]
            raise ValueError(f"{self._named(i)} fills the box's {('width', 'height')[axis]} and cannot move across "
                             f"it; give it no {('horizontal', 'vertical')[axis]} velocity "
                             f"(it has {self.velocities[i, axis]:g})")

    def _named(self, i: int) -> str:
        """A body as an error names it: a particle by its radius, a polygon as one."""
        if self.shapes[i] == POLYGON:
            return f"polygon {i}"
        if self.shapes[i] == CAPSULE:
            return f"capsule {i}"
        return f"particle {i} (radius {self.radii[i]:g})"

    def _beyond(self, i: int, lo, hi) -> str:
        """Which wall a body's extent (lo, hi) crosses, and by how much."""
        xmin, ymin, xmax, ymax = self.box
        for side, excess in (("left", xmin - lo[0]), ("right", hi[0] - xmax), ("bottom", ymin - lo[1]),
                             ("top", hi[1] - ymax)):
            if excess > 0:
                return f"{excess:.3g} beyond the box's {side} wall"
        return "outside the box"

    def copy(self, **changes) -> "World":
        """A copy, with keyword changes (e.g. restitution=0.5), validated."""
        fields = dict(positions=self.positions, velocities=self.velocities, radii=self.radii, masses=self.masses,
                      box=self.box, gravity=self.gravity, accelerations=self.accelerations, colors=self.colors,
                      restitution=self.restitution, segments=self.segments, angles=self.angles,
                      angular_velocities=self.angular_velocities, map=self.map, polygons=self.polygons,
                      friction=self.friction, damping=self.damping)
        if "gravity" in changes and "accelerations" not in changes:
            fields["accelerations"] = None   # every body follows the new gravity
        fields.update(changes)
        return World(**fields)

    def __repr__(self) -> str:
        return f"World(n={self.n}, box={self.box.tolist()}, gravity={self.gravity.tolist()}, e={self.restitution:g})"


def _rotated(offsets: np.ndarray, angles: np.ndarray) -> np.ndarray:
    """offsets (n, 2) in each body's frame, turned by its angle into the world."""
    c, s = np.cos(angles), np.sin(angles)
    return np.column_stack([c * offsets[:, 0] - s * offsets[:, 1], s * offsets[:, 0] + c * offsets[:, 1]])
