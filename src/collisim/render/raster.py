"""Off-screen drawing with OpenCV: anti-aliased shapes at sub-pixel positions.

cv2's `shift` argument takes fixed-point coordinates (value · 2^shift), so a line drawn
with SHIFT = 4 sits on a 1/16-pixel grid instead of snapping to whole pixels — motion stays
smooth at any speed. Discs and rings are drawn by the compiled rasterizer in splat.py, at float
positions and with area-exact anti-aliasing. Colours are given as RGB and drawn into BGR
canvases.
"""
from __future__ import annotations

from typing import NamedTuple

import cv2
import numpy as np

from .. import palette
from ..core.geometry.capsule import capsule_outline
from ..core.kinds import CAPSULE, CIRCLE
from . import splat

SHIFT = 4
ONE = 1 << SHIFT


def bgr(rgb) -> tuple:
    r, g, b = (int(c) for c in rgb)
    return (b, g, r)


def _or(color_rgb, default_rgb) -> tuple:
    """A colour given, else the active theme's (palette.py), read at draw time."""
    return default_rgb if color_rgb is None else color_rgb


def fixed(values) -> np.ndarray:
    """Pixel coordinates -> cv2 fixed point for `shift=SHIFT`."""
    return np.rint(np.asarray(values) * ONE).astype(np.int64)


class DiscStyle(NamedTuple):
    """What drawing discs needs besides their centres, made once for a panel whose bodies keep
    their sizes and colours: radii (n,) in pixels and colours (n, 3) in the canvas's BGR order,
    float64 and contiguous, as splat.py takes them (at 250 000 discs, converting them at every
    frame cost a third as much as drawing)."""
    radii: np.ndarray
    colors: np.ndarray


def disc_style(radii_px, colors_rgb) -> DiscStyle:
    colors = np.asarray(colors_rgb, np.float64).reshape(-1, 3)[:, ::-1]
    return DiscStyle(np.ascontiguousarray(radii_px, np.float64), np.ascontiguousarray(colors))


def draw_circles(canvas, centres_px, radii_px, colors_rgb) -> None:
    """Filled anti-aliased discs, later over earlier. centres_px: (n, 2) float pixels; radii_px:
    (n,); colors_rgb: (n, 3). One compiled call for all of them (splat.py): each pixel is
    blended by the fraction of it the disc covers, so a disc covers pi r^2 pixels whatever its
    size, and one smaller than a pixel still shows, dimmed to its area."""
    draw_styled_circles(canvas, centres_px, disc_style(radii_px, colors_rgb))


def draw_styled_circles(canvas, centres_px, style: DiscStyle) -> None:
    """draw_circles with the radii and colours of a DiscStyle made beforehand."""
    splat.draw_discs(canvas, centres_px, style.radii, style.colors)


def draw_rings(canvas, centres_px, radii_px, color_rgb, thickness: int = 2, clip=None) -> None:
    """Anti-aliased circle outlines of one colour: annuli `thickness` pixels wide centred on
    radii_px, as cv2.circle draws them (a negative thickness fills), through splat.py. clip:
    (left, top, right, bottom), the only pixels drawn (box_clip), or the whole canvas."""
    splat.draw_annuli(canvas, centres_px, radii_px, thickness, bgr(color_rgb), clip)


def draw_box(canvas, view, box, color_rgb=None, thickness: int = 2) -> None:
    xmin, ymin, xmax, ymax = box
    corners = view.to_pixels([[xmin, ymax], [xmax, ymin]])
    (x0, y0), (x1, y1) = fixed(corners).tolist()
    cv2.rectangle(canvas, (x0, y0), (x1, y1), bgr(_or(color_rgb, palette.BOX)), thickness, cv2.LINE_AA, SHIFT)


def draw_segments(canvas, view, segments, color_rgb=None, thickness: int = 3) -> None:
    """segments: (m, 4) world x0, y0, x1, y1."""
    if len(segments) == 0:
        return
    ends = fixed(view.to_pixels(np.asarray(segments).reshape(-1, 2, 2)))
    cv2.polylines(canvas, list(ends.astype(np.int32)), False, bgr(_or(color_rgb, palette.BOX)), thickness,
                  cv2.LINE_AA, SHIFT)


def map_coverage(view, collision_map, canvas_shape) -> np.ndarray:
    """Which canvas pixels (h, w) bool show solid map: the map's solid mask warped into the
    view with nearest-neighbour sampling, so each map pixel is a sharp square at any zoom.
    A map does not move: compute this once per panel."""
    m = collision_map
    height = m.solid.shape[0]
    x0, y0 = m.origin
    top_left = view.to_pixels([x0, y0 + height * m.cell])
    step = view.scale * m.cell
    # map pixel centre (column j, row i from the top) -> canvas pixel coordinates
    affine = np.array([[step, 0.0, top_left[0] + 0.5 * step - 0.5],
                       [0.0, step, top_left[1] + 0.5 * step - 0.5]])
    image = np.ascontiguousarray(m.solid[::-1]).astype(np.uint8)
    return cv2.warpAffine(image, affine, (canvas_shape[1], canvas_shape[0]), flags=cv2.INTER_NEAREST,
                          borderMode=cv2.BORDER_CONSTANT, borderValue=0).astype(bool)


def draw_map(canvas, view, collision_map, coverage, color_rgb=None, shade: float = 0.3) -> None:
    """A collision map as the level it is: its solid pixels (`coverage`, from map_coverage)
    shaded a fraction `shade` toward the box colour, and its contour chains as outlines."""
    color = np.array(bgr(_or(color_rgb, palette.BOX)), np.float32)
    canvas[coverage] = ((1.0 - shade) * canvas[coverage] + shade * color).astype(np.uint8)
    polylines = [fixed(view.to_pixels(chain)).astype(np.int32) for chain in collision_map.chains]
    cv2.polylines(canvas, polylines, True, bgr(_or(color_rgb, palette.BOX)), 1, cv2.LINE_AA, SHIFT)


def box_clip(canvas, view, box) -> tuple:
    """The canvas pixels inside the box's outline: (left, top, right, bottom), columns
    [left, right) and rows [top, bottom), as splat.py's clip."""
    (x0, y0), (x1, y1) = np.rint(view.to_pixels([box[:2], box[2:]])).astype(int)
    return splat.clip_rect(canvas, (x0, y1, x1 + 1, y0 + 1))


def box_region(canvas, clip) -> tuple:
    """The pixels of a clip (box_clip: those inside the box's outline) as a view of the canvas
    (drawing into it draws into the canvas, and nothing drawn there can leave the box), and its
    top-left corner in pixels."""
    left, top, right, bottom = clip
    return canvas[top:bottom, left:right], np.array([left, top], np.float64)


TRAIL_SHARE = 0.75   # a trail's colour: this share of the body's, the rest the background's


def draw_trails(canvas, view, history, colors_rgb, thickness: int = 2, offset=(0.0, 0.0)) -> None:
    """Motion trails: history (T, n, 2) world positions, oldest first, one polyline call per
    colour, `thickness` pixels wide (2 at least: a 1-pixel line of a dimmed colour does not
    survive H.264's chroma subsampling). `offset`: the canvas's top-left corner in the view's
    pixels (box_region)."""
    if len(history) < 2:
        return
    paths = fixed(view.to_pixels(np.swapaxes(history, 0, 1)) - offset).astype(np.int32)  # (n, T, 2)
    colors = np.asarray(colors_rgb)
    for color in np.unique(colors, axis=0):
        same = np.all(colors == color, axis=1)
        dim = tuple(int(c * TRAIL_SHARE + (1 - TRAIL_SHARE) * b) for c, b in zip(color, palette.BACKGROUND))
        cv2.polylines(canvas, list(paths[same]), False, bgr(dim), thickness, cv2.LINE_AA, SHIFT)


def draw_arrows(canvas, view, positions, velocities, seconds: float, radii=None, color_rgb=None,
                thickness: int = 2, offset=(0.0, 0.0), box=None) -> None:
    """Velocity arrows from each body's rim (its centre if no radii), as long as the distance it
    would cover in `seconds`: a slow body's arrow starts outside it instead of hiding inside.
    With `box`, an arrow that would leave it is shortened to end at its wall (head and all).
    `offset` as in draw_trails."""
    velocities = np.asarray(velocities, np.float64)
    speed = np.hypot(velocities[:, 0], velocities[:, 1])
    moving = speed > 0
    rims = np.zeros_like(velocities) if radii is None else \
        velocities / np.where(moving, speed, 1.0)[:, None] * np.broadcast_to(radii, speed.shape)[:, None]
    tails = np.asarray(positions)[moving] + rims[moving]
    steps = velocities[moving] * seconds
    if box is not None:
        steps *= share_inside(tails, steps, box)[:, None]
    starts = view.to_pixels(tails) - offset
    ends = view.to_pixels(tails + steps) - offset
    color = bgr(_or(color_rgb, palette.TEXT))
    tip = 5.0 * thickness   # the head's size in pixels, whatever the arrow's length
    for (x0, y0), (x1, y1), length in zip(fixed(starts).tolist(), fixed(ends).tolist(),
                                          np.hypot(*(ends - starts).T).tolist()):
        cv2.arrowedLine(canvas, (x0, y0), (x1, y1), color, thickness, cv2.LINE_AA, SHIFT,
                        min(0.5, tip / max(length, 1.0)))


def share_inside(starts, steps, box) -> np.ndarray:
    """(k,) the largest share in [0, 1] of each step from its start that stays in the box."""
    share = np.ones(len(starts))
    for axis in range(2):
        lo, hi, step = box[axis], box[axis + 2], steps[:, axis]
        room = np.where(step > 0, hi - starts[:, axis], lo - starts[:, axis])
        with np.errstate(divide="ignore", invalid="ignore"):
            share = np.minimum(share, np.where(step != 0, room / step, 1.0))
    return np.clip(share, 0.0, 1.0)


def draw_text(canvas, text: str, origin, scale: float = 0.55, color_rgb=None,
              thickness: int = 1, anchor: str = "left") -> None:
    """Text whose baseline starts at origin (pixels); anchor 'center' centres it on origin, 'right' ends it there."""
    font = cv2.FONT_HERSHEY_SIMPLEX
    x, y = origin
    if anchor in ("center", "right"):
        (width, _), _ = cv2.getTextSize(text, font, scale, thickness)
        x -= width // 2 if anchor == "center" else width
    cv2.putText(canvas, text, (int(x), int(y)), font, scale, bgr(_or(color_rgb, palette.TEXT)), thickness,
                cv2.LINE_AA)


def draw_lines(canvas, view, starts, ends, color_rgb, thickness: int = 1) -> None:
    """World-space line segments from starts (k, 2) to ends (k, 2)."""
    color = bgr(color_rgb)
    for (x0, y0), (x1, y1) in zip(fixed(view.to_pixels(starts)).tolist(), fixed(view.to_pixels(ends)).tolist()):
        cv2.line(canvas, (x0, y0), (x1, y1), color, thickness, cv2.LINE_AA, SHIFT)


def draw_rects(canvas, view, lo, hi, color_rgb, thickness: int = 1) -> None:
    """World-space axis-aligned rectangles with corners lo (k, 2) and hi (k, 2); thickness -1 fills."""
    color = bgr(color_rgb)
    top_left = fixed(view.to_pixels(np.column_stack([np.asarray(lo)[:, 0], np.asarray(hi)[:, 1]]))).tolist()
    bottom_right = fixed(view.to_pixels(np.column_stack([np.asarray(hi)[:, 0], np.asarray(lo)[:, 1]]))).tolist()
    for (x0, y0), (x1, y1) in zip(top_left, bottom_right):
        cv2.rectangle(canvas, (x0, y0), (x1, y1), color, thickness, cv2.LINE_AA, SHIFT)


def draw_polygons(canvas, outlines_px, colors_rgb) -> None:
    """Filled anti-aliased convex polygons, later over earlier, each with an edge line so a face
    reads against its neighbour. outlines_px: a list of (k, 2) float pixel arrays; colors_rgb:
    (m, 3), one per polygon."""
    for outline, color in zip(outlines_px, colors_rgb):
        points = fixed(outline).astype(np.int32)
        cv2.fillConvexPoly(canvas, points, bgr(color), lineType=cv2.LINE_AA, shift=SHIFT)
        edge = tuple(int(0.6 * c) for c in bgr(color))
        cv2.polylines(canvas, [points], True, edge, 1, lineType=cv2.LINE_AA, shift=SHIFT)


def polygon_outlines(world, positions, angles) -> tuple[list, np.ndarray]:
    """The world outlines (k, 2) of every polygon and capsule body at these poses (a capsule's
    sampled finely round its caps), and their body indices."""
    bodies = np.flatnonzero(world.shapes != CIRCLE)   # the bodies of the vertex table
    outlines = np.split(world.placed_vertices(positions, angles), world.vertex_start[bodies[1:]])
    for k in np.flatnonzero(world.shapes[bodies] == CAPSULE):
        outlines[k] = capsule_outline(outlines[k][0], outlines[k][1], world.capsule_radii[bodies[k]])
    return outlines, bodies


def draw_lines_px(canvas, starts, ends, color_rgb, thickness: int = 1) -> None:
    """Pixel-space line segments from starts (k, 2) to ends (k, 2), at sub-pixel positions."""
    color = bgr(color_rgb)
    for (x0, y0), (x1, y1) in zip(fixed(starts).tolist(), fixed(ends).tolist()):
        cv2.line(canvas, (x0, y0), (x1, y1), color, thickness, cv2.LINE_AA, SHIFT)


def draw_rect_px(canvas, corner_a, corner_b, color_rgb, thickness: int = 1) -> None:
    """A pixel-space rectangle between two corners; thickness -1 fills."""
    (x0, y0), (x1, y1) = fixed([corner_a, corner_b]).tolist()
    cv2.rectangle(canvas, (x0, y0), (x1, y1), bgr(color_rgb), thickness, cv2.LINE_AA, SHIFT)
