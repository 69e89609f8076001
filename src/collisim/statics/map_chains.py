"""The exact side of a collision map: closed polygons along the boundary of its solid pixels.

OpenCV traces every border of the solid mask (cv2.findContours, RETR_CCOMP: outer borders and
the borders of holes, CHAIN_APPROX_NONE: every boundary pixel), through the centres of the solid
boundary pixels. Each contour is then

1. given back the corner pixels the 8-connected trace cuts off at concave corners (a horizontal
   run, one diagonal step, a vertical run), so a room's corner stays square;
2. simplified (cv2.approxPolyDP, epsilon = `simplify` pixels): straight runs become single
   edges; then each staircase (a stretch running one way in x and in y) again, to STAIRS
   pixels, so a painted slope becomes one slanted edge;
3. moved outward, toward free space, by half a pixel, from the pixel centres onto the pixel
   edges: each vertex moves along the bisector of its two edge normals by 0.5 / cos(half the
   turn) pixels (the miter, clamped to one pixel at sharp concave turns). A convex turn sharper
   than a right angle, such as the end of a one-pixel line, gets a square cap of two vertices.

Axis-aligned runs therefore lie exactly on the pixel edges; elsewhere a chain is within
`simplify` + 1/2 pixel of the union of solid pixel squares, and where a staircase was made
straight (step 2's second pass, _straighten_staircases) within STAIRS + 1/sqrt(2).

The mask is padded with one free pixel all round before tracing: beyond the image counts as
free, so a solid region touching the image border is closed along the border.

Coordinates here are pixel units of the mask (row 0 = the lowest y): x = column, y = row, and
pixel (row i, column j) is the unit square centred on (j, i).
"""
import cv2
import numpy as np

# OpenCV traces outer and hole borders alike with the solid on the right of the direction of
# travel in (column, row) coordinates. The signed area decides instead wherever it is not zero
# (tests/test_collision_map.py checks that the two agree); a contour of zero area, a line one
# pixel wide, has only this to go by.
FREE_SIDE_OF_OPENCV_TRACE = -1
# Pixels: how far a staircase's straightened edges may stray from its pixel centres. A digital
# straight line's centres lie in a strip up to a pixel wide, so less leaves a gentle slope a
# run of kinks that ccd meets as impacts (tests/test_map_seams.py).
STAIRS = 1.0


def trace_chains(solid: np.ndarray, simplify: float) -> list:
    """Closed polygons (p, 2) float64 in pixel units along the borders of solid (ny, nx) bool,
    in OpenCV's order: each polygon's last vertex joins its first."""
    padded = np.pad(solid, 1).astype(np.uint8)
    contours, hierarchy = cv2.findContours(padded, cv2.RETR_CCOMP, cv2.CHAIN_APPROX_NONE)
    chains = []
    for contour, links in zip(contours, hierarchy[0] if len(contours) else ()):
        points = contour[:, 0, :].astype(np.int64)
        side = free_side(points, hole=links[3] >= 0)
        points = _restore_concave_corners(points, padded, side)
        corners = cv2.approxPolyDP(points.astype(np.int32).reshape(-1, 1, 2), float(simplify), True)[:, 0, :]
        chains.append(_onto_pixel_edges(_straighten_staircases(corners).astype(np.float64), side) - 1.0)  # unpad
    return chains


def _straighten_staircases(corners: np.ndarray) -> np.ndarray:
    """The closed polygon corners (p, 2) int with its staircases made straight: each stretch
    along which x and y both run one way (a monotone stretch; its ends, where either turns back,
    are kept, as is every corner joining two axis-aligned edges, pixel art's square corners)
    simplified again to within STAIRS pixels (cv2.approxPolyDP, open), so a slanted or curved
    edge painted as pixel steps becomes slanted edges. Each new edge joins two corners of the stretch, so
    it stays within the strip of pixel centres its stretch lies in: the two sides of a thin
    wall, each monotone, do not cross."""
    p = len(corners)
    if p < 4:
        return corners
    step = np.sign(np.roll(corners, -1, axis=0) - corners)   # step k: corner k -> k + 1
    square = _axis_aligned(step) & _axis_aligned(np.roll(step, 1, axis=0))   # pixel art's corners
    ends = np.union1d(_turning_back(step), np.flatnonzero(square))
    if len(ends) == 0:
        return corners
    kept = []
    for a, b in zip(ends, np.roll(ends, -1)):
        stretch = np.take(corners, np.arange(a, b + (p if b <= a else 0) + 1), axis=0, mode="wrap")
        straight = cv2.approxPolyDP(stretch.astype(np.int32).reshape(-1, 1, 2), STAIRS, False)[:, 0, :]
        kept.append(straight[:-1])   # its last corner starts the next stretch
    return np.concatenate(kept).astype(corners.dtype)


def _turning_back(step: np.ndarray) -> np.ndarray:
    """The corners k at which the closed polygon's x or y turns back: step k (the sign of corner
    k -> k + 1, (p, 2)) is the opposite of the last non-zero step along that axis before it
    (the turn may pass through steps along the other axis only)."""
    last = [int(next((v for v in step[::-1, axis] if v != 0), 0)) for axis in range(2)]
    ends = []
    for k in range(len(step)):
        back = False
        for axis in range(2):
            sign = int(step[k, axis])
            if sign != 0:
                back = back or sign == -last[axis]
                last[axis] = sign
        if back:
            ends.append(k)
    return np.array(ends, np.int64)


def free_side(points: np.ndarray, hole: bool) -> int:
    """+1 when free space lies to the right of the direction of travel along a contour, -1 when
    to the left. An outer border encloses solid and a hole's border encloses free space, and a
    positive signed area means the enclosed side is on the left."""
    x, y = points[:, 0].astype(np.float64), points[:, 1].astype(np.float64)
    twice_area = float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))
    if twice_area == 0.0:
        return FREE_SIDE_OF_OPENCV_TRACE
    return int(np.sign(twice_area)) * (-1 if hole else 1)


def _turns(before: np.ndarray, after: np.ndarray) -> np.ndarray:
    """The z component of before × after for rows of 2-D vectors: > 0 for a left turn."""
    return before[:, 0] * after[:, 1] - before[:, 1] * after[:, 0]


def _axis_aligned(steps: np.ndarray) -> np.ndarray:
    """(q,) bool: which integer steps (q, 2) move along exactly one axis."""
    return (steps[:, 0] == 0) != (steps[:, 1] == 0)


def _restore_concave_corners(points: np.ndarray, padded: np.ndarray, side: int) -> np.ndarray:
    """The contour (q, 2) int64 with the solid pixel put back into every diagonal step that joins
    two perpendicular axis-aligned steps at a concave turn (a left turn when free space is on the
    left): a -> b becomes a -> a + (previous step) -> b, which runs along two pixel edges."""
    if len(points) < 3:
        return points
    step = np.roll(points, -1, axis=0) - points           # step k: point k -> point k + 1
    before, after = np.roll(step, 1, axis=0), np.roll(step, -1, axis=0)
    corner = points + before
    restore = (_axis_aligned(before) & _axis_aligned(after) & np.all(step == before + after, axis=1)
               & (side * _turns(before, after) < 0))
    restore[restore] = padded[corner[restore, 1], corner[restore, 0]] > 0   # solid, as it must be
    if not restore.any():
        return points
    count = 1 + restore
    out = np.empty((int(count.sum()), 2), np.int64)
    start = np.cumsum(count) - count
    out[start] = points
    out[start[restore] + 1] = corner[restore]
    return out


def _onto_pixel_edges(corners: np.ndarray, side: int) -> np.ndarray:
    """The closed polygon through boundary pixel centres corners (p, 2), moved half a pixel
    toward free space (see the module docstring)."""
    distinct = np.any(corners != np.roll(corners, 1, axis=0), axis=1)
    corners = corners[distinct] if distinct.any() else corners[:1]
    if len(corners) == 1:   # a lone pixel: its square, traversed like OpenCV's contours
        return corners + 0.5 * np.array([[-1.0, -1.0], [-1.0, 1.0], [1.0, 1.0], [1.0, -1.0]])
    edge = np.roll(corners, -1, axis=0) - corners
    tangent = edge / np.hypot(edge[:, 0], edge[:, 1])[:, None]        # of the edge leaving corner k
    normal = side * np.column_stack((tangent[:, 1], -tangent[:, 0]))  # outward: toward free space
    tangent_in, normal_in = np.roll(tangent, 1, axis=0), np.roll(normal, 1, axis=0)
    cos_turn = np.sum(tangent_in * tangent, axis=1)
    # (n_in + n) / (2 (1 + cos turn)) has length 0.5 / cos(turn / 2) along the bisector;
    # clamped to one pixel for concave turns sharper than 120 degrees.
    miter = (normal_in + normal) / (2.0 * np.maximum(1.0 + cos_turn, 0.5))[:, None]
    cap = (cos_turn < 0.0) & (side * _turns(tangent_in, tangent) >= 0.0)   # sharp and convex
    first = corners + np.where(cap[:, None], 0.5 * (normal_in + tangent_in), miter)
    second = corners + 0.5 * (normal - tangent)
    count = 1 + cap
    out = np.empty((int(count.sum()), 2))
    start = np.cumsum(count) - count
    out[start] = first
    out[start[cap] + 1] = second[cap]
    return out
