"""Collision maps: a level's collisions precomputed from a bitmap, saved to a file, loaded at start.

A map is made once from an image (CollisionMap.from_image; dark pixels are solid) and holds two
answers to "where is the level?":

* a signed distance grid sampled at pixel centres (map_field.py): O(1) per query anywhere, for
  the discrete step (map_sample, compiled), as accurate as the map's resolution;
* exact segment chains along the pixel edges (map_chains.py), for ccd and for drawing.

Reading the image and drawing one from exact shapes (rasterize_polygons) is map_image.py.

Conventions. World y points up and image rows go down, so every stored grid is flipped: row 0 is
the lowest y. `origin` is the world position of the image's lower-left corner and `cell` the side
of one pixel: pixel (row i from the bottom, column j) is the square
[ox + j*cell, ox + (j+1)*cell] x [oy + i*cell, oy + (i+1)*cell], and the solid region is the union
of the solid pixel squares. Outside the image the distance field repeats its border (make the map
cover the world box), while the chains treat everything beyond the image as free.

The file (save, load) is a versioned npz written under a temporary name and renamed, so a failed
save leaves nothing behind. Everything is deterministic: the same image gives the same bytes.
"""
from __future__ import annotations

import zipfile
import zlib
from pathlib import Path

import numpy as np

from ..core.files import written_whole
from ..core.checks import StaticMap, number
from .map_chains import trace_chains
from .map_field import MapField, has_map, make_field, map_sample, no_map_field, sample_points, signed_distance_grid
from .map_image import rasterize_polygons, solid_mask, world_origin

__all__ = ["CollisionMap", "MapField", "map_sample", "has_map", "no_map_field", "rasterize_polygons", "MAP_FORMAT"]

MAP_FORMAT = 1   # the version of the map file written by save()
_FILE_KEYS = ("map_format", "solid", "distance", "cell", "origin", "segments", "chain_vertices", "chain_offsets")


class CollisionMap(StaticMap):
    """A level precomputed from a bitmap (made by from_image or load).

    solid: (ny, nx) bool            the solid pixels, row 0 = the lowest y
    distance_grid: (ny, nx) float64 signed distance at pixel centres (world units, + free, - solid)
    cell: float                     the side of one pixel in world units
    origin: (2,) float64            world position of the lower-left corner
    segments: (k, 4) float64        rows x0, y0, x1, y1: every chain's edges, each chain closed
    chains: list of (p, 2) float64  closed polygons along the solid region's pixel edges
    field: MapField                 what the compiled step samples (map_sample)
    """

    def __init__(self, solid, distance_grid, cell, origin, segments, chains):
        self.solid = solid
        self.distance_grid = distance_grid
        self.cell = float(cell)
        self.origin = origin
        self.segments = segments
        self.chains = chains
        self._field = make_field(distance_grid, cell, origin)

    @classmethod
    def from_image(cls, image, cell=1.0, origin=(0.0, 0.0), threshold=0.5, channel=None,
                   simplify=0.25) -> "CollisionMap":
        """A map from a bitmap: a path (read by OpenCV, any format it reads) or an array.

        image: (h, w) grayscale or (h, w, 3|4) RGB(A) array (a file's BGR(A) is reordered),
        uint8, uint16 or float in [0, 1]. A pixel is solid when its brightness is below
        `threshold` (in (0, 1]): grayscale, the mean of R, G and B, or the value of `channel`
        (an index or "r", "g", "b", "a"). In an RGBA image fully transparent pixels are free,
        unless channel="a", where the alpha itself is the value tested.
        cell: world units per pixel; origin: world (x, y) of the image's lower-left corner;
        simplify: the chains' polygon simplification tolerance, in pixels.
        """
        cell = number("cell", cell, positive=True)
        origin = world_origin(origin)
        threshold = number("threshold", threshold)
        if not 0.0 < threshold <= 1.0:
            raise ValueError(f"threshold must be in (0, 1], got {threshold:g}")
        simplify = number("simplify", simplify)
        if simplify < 0.0:
            raise ValueError(f"simplify must be >= 0 (pixels), got {simplify:g}")
        solid = solid_mask(image, threshold, channel)
        if not solid.any():
            raise ValueError(f"the map image has no solid pixel: none is darker than threshold {threshold:g}")
        if solid.all():
            raise ValueError(f"the map image is solid everywhere: no pixel is as bright as threshold {threshold:g}")
        chains = [origin + (chain + 0.5) * cell for chain in trace_chains(solid, simplify)]
        return cls(solid, signed_distance_grid(solid, cell), cell, origin, _chain_segments(chains), chains)

    @property
    def field(self) -> MapField:
        return self._field

    @property
    def shape(self) -> tuple:
        """(ny, nx): pixel rows and columns."""
        return self.solid.shape

    @property
    def bounds(self) -> tuple:
        """(x0, y0, x1, y1): the world rectangle the image covers."""
        ny, nx = self.shape
        x0, y0 = (float(v) for v in self.origin)
        return x0, y0, x0 + nx * self.cell, y0 + ny * self.cell

    def sample(self, points):
        """(distances (m,), normals (m, 2)) at points (m, 2), in one compiled call (map_sample);
        for a single point (2,): (float, (2,))."""
        points, single = _points(points)
        distances, normals = np.empty(len(points)), np.empty((len(points), 2))
        sample_points(self._field, points, distances, normals)
        return (float(distances[0]), normals[0]) if single else (distances, normals)

    def distance(self, points):
        """Signed distance (m,) at points (m, 2): > 0 free, < 0 solid; a float for one point (2,)."""
        return self.sample(points)[0]

    def normal(self, points):
        """Unit normals (m, 2) toward free space at points (m, 2), (0, 0) where the field is
        flat; (2,) for one point (2,)."""
        return self.sample(points)[1]

    def to_arrays(self) -> dict:
        """The map as the named arrays of its file (a trajectory file embeds them too)."""
        offsets = np.concatenate([[0], np.cumsum([len(chain) for chain in self.chains])]).astype(np.int64)
        return dict(map_format=np.array(MAP_FORMAT, np.int64), solid=self.solid, distance=self.distance_grid,
                    cell=np.array(self.cell), origin=self.origin, segments=self.segments,
                    chain_vertices=np.concatenate(self.chains).reshape(-1, 2), chain_offsets=offsets)

    def save(self, path) -> Path:
        """Write the map to a versioned .npz file (under a temporary name, renamed when complete)."""
        path = Path(path)
        arrays = self.to_arrays()
        with written_whole(path, "collision map") as temporary, open(temporary, "wb") as file:
            np.savez_compressed(file, **arrays)
        return path

    @classmethod
    def load(cls, path) -> "CollisionMap":
        """Read a file written by save: the same arrays, byte for byte. A missing, broken or
        foreign file, or one of another format version, raises ValueError with one line."""
        path = Path(path)
        return cls.from_arrays(_read_npz(path), path)

    @classmethod
    def from_arrays(cls, arrays: dict, path) -> "CollisionMap":
        """The map whose arrays (to_arrays) were read from `path` (named in errors)."""
        version = arrays.get("map_format")
        if version is None:
            raise ValueError(f"cannot read collision map {path}: not a collisim collision map file")
        if version.shape != () or version.dtype.kind not in "iu" or int(version) != MAP_FORMAT:
            raise ValueError(f"collision map file {path} has format version {version.tolist()!r:.20}; "
                             f"this collisim reads version {MAP_FORMAT}")
        if set(arrays) != set(_FILE_KEYS) or not _consistent(arrays):
            raise ValueError(f"cannot read collision map {path}: the file is damaged")
        offsets, vertices = arrays["chain_offsets"], arrays["chain_vertices"]
        chains = [vertices[a:b].copy() for a, b in zip(offsets[:-1], offsets[1:])]
        return cls(arrays["solid"], arrays["distance"], float(arrays["cell"]), arrays["origin"],
                   arrays["segments"], chains)

    def __repr__(self) -> str:
        ny, nx = self.shape
        x0, y0, x1, y1 = self.bounds
        return (f"CollisionMap({nx}x{ny} pixels of {self.cell:g}, bounds=({x0:g}, {y0:g}, {x1:g}, {y1:g}), "
                f"{len(self.chains)} chains, {len(self.segments)} segments)")


# ---------------------------------------------------------------- helpers

def _chain_segments(chains: list) -> np.ndarray:
    """(k, 4) rows x0, y0, x1, y1: every edge of every closed chain, the last vertex to the first."""
    rows = [np.column_stack((chain, np.roll(chain, -1, axis=0))) for chain in chains]
    return np.concatenate(rows) if rows else np.zeros((0, 4))


def _points(points) -> tuple:
    """(points (m, 2) float64 C-contiguous, single) from (m, 2) or one point (2,)."""
    try:
        array = np.ascontiguousarray(points, dtype=np.float64)
    except (TypeError, ValueError):
        raise ValueError(f"points must be numbers, got {points!r:.40}") from None
    single = array.shape == (2,)
    if single:
        array = array[None]
    if array.ndim != 2 or array.shape[1] != 2:
        raise ValueError(f"points must have shape (m, 2) or (2,), got shape {array.shape}")
    if np.isnan(array).any():
        raise ValueError("points contain NaN")
    return array, single


# ---------------------------------------------------------------- the map file

def _read_npz(path: Path) -> dict:
    """Every array of an npz file, or ValueError with one line."""
    try:
        with np.load(path, allow_pickle=False) as data:
            return {key: data[key] for key in data.files}
    except FileNotFoundError:
        raise ValueError(f"cannot read collision map {path}: not found") from None
    except (OSError, ValueError, KeyError, EOFError, AttributeError, TypeError, zipfile.BadZipFile, zlib.error):
        raise ValueError(f"cannot read collision map {path}: not a collisim collision map file") from None


def _consistent(arrays: dict) -> bool:
    """Do the arrays of a map file have the types and shapes save() writes?"""
    solid, distance, origin, cell = arrays["solid"], arrays["distance"], arrays["origin"], arrays["cell"]
    segments, vertices, offsets = arrays["segments"], arrays["chain_vertices"], arrays["chain_offsets"]
    floats = all(a.dtype == np.float64 for a in (distance, origin, cell, segments, vertices))
    return (floats and solid.dtype == np.bool_ and solid.ndim == 2 and distance.shape == solid.shape
            and solid.size > 1 and origin.shape == (2,) and cell.shape == () and float(cell) > 0.0
            and bool(np.all(np.isfinite(distance))) and segments.ndim == 2 and segments.shape[1] == 4
            and vertices.ndim == 2 and vertices.shape[1] == 2 and offsets.dtype == np.int64
            and offsets.ndim == 1 and len(offsets) >= 1 and offsets[0] == 0 and offsets[-1] == len(vertices)
            and bool(np.all(np.diff(offsets) >= 0)))
