"""The compiled side of a collision map: its signed distance grid and the sampler the engine calls.

The grid holds the signed distance to the solid region at every pixel centre (positive in free
space, negative inside solid, in world units). It comes from an exact Euclidean distance
transform of the pixel mask, taken twice: on the free pixels (how far to the nearest solid pixel
centre) and on the solid ones (how far to the nearest free pixel centre). Half a pixel is
subtracted from both, so a free centre next to a solid one is +cell/2, the solid centre across
the edge is -cell/2, and the straight pixel edge between them interpolates to exactly 0.

Only pixels inside the image count: nothing beyond the image pulls or pushes (the contour
chains differ there, see map_chains.py). Sampling between pixel centres is bilinear; outside the
centres' rectangle the point is clamped onto it (the half-pixel rim of the image and anything
beyond take the border samples), so a map should cover the world box.

Accuracy is the map's resolution: at pixel centres the grid is within (sqrt(2) - 1)/2 of a pixel
of the exact distance to the union of solid pixel squares (exact where the nearest solid lies
straight across an axis-aligned edge), and that union is itself within sqrt(2)/2 of a pixel of
the shape the image was drawn from.
"""
from collections import namedtuple
import math

import cv2
import numpy as np

from ..core.compiling import kernel

DEPTH_SLACK = 0.5   # pixels: how far a contact's depth may read from the field at its centre (map_contact)
CORNER_COS = math.cos(math.radians(45.0))   # end normals further apart than this: a corner (map_contact)
DEPTH_TAPS = 4      # samples each side of the centre averaged along the outline for a contact's depth

MapField = namedtuple("MapField", ["x0", "y0", "cell", "nx", "ny", "distance"])
MapField.__doc__ = """A collision map as the compiled step sees it (CollisionMap.field, or no_map_field()).

x0, y0 (float): world coordinates of the image's lower-left corner; cell (float): the side of one
pixel; nx, ny (int): pixels per row and per column; distance (ny, nx) float64, C-contiguous: the
signed distance at pixel centres, row 0 the lowest y. Sample (i, j) sits at
(x0 + (j + 0.5) * cell, y0 + (i + 0.5) * cell)."""


def make_field(distance, cell, origin) -> MapField:
    """The MapField of a distance grid (ny, nx), with the exact numba types every field shares."""
    distance = np.ascontiguousarray(distance, dtype=np.float64)
    ny, nx = distance.shape
    return MapField(float(origin[0]), float(origin[1]), float(cell), int(nx), int(ny), distance)


def no_map_field() -> MapField:
    """The field of a world without a map: one sample of +inf, so the engine can pass a field
    unconditionally (same numba types) and ask has_map before sampling."""
    return make_field(np.full((1, 1), np.inf), 1.0, (0.0, 0.0))


@kernel
def has_map(field):
    """False for no_map_field() (a real map's distances are all finite)."""
    return math.isfinite(field.distance[0, 0])


@kernel
def _grid_position(x, x0, cell, n):
    """Where coordinate x falls among n samples along one axis: (k, f), the sample k at or below
    x and the fraction f in [0, 1] of the way to sample k + 1. Clamped to the samples (NaN goes
    to the first one); a single-sample axis gives (0, 0.0)."""
    u = (x - x0) / cell - 0.5
    if not u > 0.0:
        return 0, 0.0
    if u >= n - 1:
        return (n - 2, 1.0) if n > 1 else (0, 0.0)
    k = int(u)
    return k, u - k


@kernel
def _central_difference(grid, i, j):
    """The grid's slope at sample (i, j): central differences, one-sided at the border."""
    ny, nx = grid.shape
    gx = grid[i, min(j + 1, nx - 1)] - grid[i, max(j - 1, 0)]
    gy = grid[min(i + 1, ny - 1), j] - grid[max(i - 1, 0), j]
    return gx, gy


@kernel
def map_sample(field, x, y):
    """The signed distance d at world point (x, y) and the unit normal (nx, ny) toward free space.

    d is the bilinear interpolant of the four surrounding samples; the normal is its gradient
    (the analytic derivative), normalized. Where that gradient vanishes (a ridge or a valley of
    the field, or a flat clamped border) the normal falls back to central differences of the grid
    at the nearest sample, and where those vanish too it is (0, 0). Outside the samples the point
    is clamped onto them: the value and the normal are those of the nearest border point.
    With no_map_field() the answer is (inf, 0, 0).
    """
    if not has_map(field):
        return np.inf, 0.0, 0.0
    grid = field.distance
    j, fx = _grid_position(x, field.x0, field.cell, field.nx)
    i, fy = _grid_position(y, field.y0, field.cell, field.ny)
    j1, i1 = min(j + 1, field.nx - 1), min(i + 1, field.ny - 1)
    bottom = grid[i, j] + fx * (grid[i, j1] - grid[i, j])
    top = grid[i1, j] + fx * (grid[i1, j1] - grid[i1, j])
    d = bottom + fy * (top - bottom)
    # Derivatives per sample spacing (the direction is all the normal needs).
    gx = (1.0 - fy) * (grid[i, j1] - grid[i, j]) + fy * (grid[i1, j1] - grid[i1, j])
    gy = top - bottom
    if gx == 0.0 and gy == 0.0:
        gx, gy = _central_difference(grid, i1 if fy >= 0.5 else i, j1 if fx >= 0.5 else j)
    length = math.hypot(gx, gy)
    if length == 0.0:
        return d, 0.0, 0.0
    return d, gx / length, gy / length


@kernel
def map_contact(field, x, y, radius):
    """What a body of `radius` centred at (x, y) meets: (depth, nx, ny), the distance from the
    map and the unit normal toward free space, both read across the body rather than at a point.

    A slanted outline is a staircase of pixels, and the distance to a staircase is bumpy: along a
    painted 20-degree slope the field a radius out rises and falls by 0.4 of a pixel between the
    steps' corners, and its normal swings by degrees. A body held on it by the contact solver
    would be lifted off at each corner and land again faster than the rest speed: a bounce logged
    as a collision, and energy lost, a quarter of the acceleration down the slope at 8 pixels a
    radius. So the contact reads the grid (which stays the exact distance to the pixels) as the
    body spans it:

    * the normal from the field's central differences a radius either side (at least half a
      pixel); where they nearly cancel (the body straddles a ridge of the field, such as a thin
      corridor's middle) the field's own normal at the centre (map_sample's);
    * the depth, the field averaged along the outline (perpendicular to that normal) across the
      body's width, kept within DEPTH_SLACK pixels of the field's value at the centre. A straight
      outline reads exactly (the average of a linear field is its value); a staircase reads as
      the slope it draws; a sharp corner, whose distance the average overstates, lets a body in
      by at most DEPTH_SLACK pixels. Both settle as the map gets finer than the body;
    * except in a corner: where the field's own normals a radius either side along the outline
      differ by more than 45 degrees, two surfaces meet under the body (the bottom of a V, a
      room's corner) and their average would be neither; the contact is read at the centre, as
      map_sample reads it, its normal that of the nearer surface. A staircase's normals swing by
      less (tests/test_map_seams.py)."""
    d, fx, fy = map_sample(field, x, y)
    h = max(radius, 0.5 * field.cell)
    gx = map_sample(field, x + h, y)[0] - map_sample(field, x - h, y)[0]
    gy = map_sample(field, x, y + h)[0] - map_sample(field, x, y - h)[0]
    length = math.hypot(gx, gy)
    if not length > h:   # a slope under 1/2 (true distance has 1): a ridge, or NaN
        return d, fx, fy
    nx, ny = gx / length, gy / length
    _, ax, ay = map_sample(field, x - h * ny, y + h * nx)   # the field's own normals a radius either
    _, bx, by = map_sample(field, x + h * ny, y - h * nx)   # side along the outline
    if ax * bx + ay * by < CORNER_COS:   # two surfaces meet under the body: a corner, read exactly
        return d, fx, fy
    taps = min(int(math.ceil(h / field.cell)), DEPTH_TAPS)   # each side: a pixel apart, at most DEPTH_TAPS
    total = d
    for k in range(1, taps + 1):
        s = h * k / taps
        total += map_sample(field, x - s * ny, y + s * nx)[0] + map_sample(field, x + s * ny, y - s * nx)[0]
    slack = DEPTH_SLACK * field.cell
    return min(max(total / (2 * taps + 1), d - slack), d + slack), nx, ny


@kernel
def sample_points(field, points, distances, normals):
    """map_sample at every row of points (m, 2), into distances (m,) and normals (m, 2)."""
    for k in range(points.shape[0]):
        d, nx, ny = map_sample(field, points[k, 0], points[k, 1])
        distances[k] = d
        normals[k, 0] = nx
        normals[k, 1] = ny


def signed_distance_grid(solid: np.ndarray, cell: float) -> np.ndarray:
    """(ny, nx) float64, C-contiguous: the signed distance at each pixel centre of the mask solid
    (ny, nx) bool, in world units (positive free, negative solid, edges at 0). The mask must hold
    both solid and free pixels."""
    grid = _pixel_distances(~solid)       # at free pixels: to the nearest solid centre
    grid -= 0.5
    np.subtract(0.5, _pixel_distances(solid), out=grid, where=solid)   # to the nearest free centre
    grid *= cell
    return grid


def _pixel_distances(mask: np.ndarray) -> np.ndarray:
    """(ny, nx) float64: at each pixel of mask, the exact Euclidean distance (in pixels) to the
    nearest pixel outside it; 0 outside.

    OpenCV's precise transform returns float32. A distance between pixel centres is the square
    root of an integer, so the square is snapped to that integer and rooted again in float64:
    exact below 2048 pixels (a correctly rounded float32 root squares to within 1/2 of its
    integer there), and never meaningfully worse than the float32 value beyond."""
    distance = cv2.distanceTransform(mask.astype(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE).astype(np.float64)
    np.square(distance, out=distance)
    np.rint(distance, out=distance)
    return np.sqrt(distance, out=distance)
