"""Collision maps (collisim.statics.collision_map): a bitmap made into a signed distance field and
exact segment chains, saved to a file and loaded.

Shapes are drawn with rasterize_polygons (itself checked against shapely below) and measured
against closed forms (a disc's |p - c| - R, an axis-aligned rectangle's distance) or against
shapely's union of the solid pixel squares, the region a map stands for.
"""
from functools import reduce

import cv2
import numpy as np
import pytest
from numba import njit

import collisim
from collisim.statics.collision_map import (MAP_FORMAT, CollisionMap, MapField, has_map, map_sample, no_map_field,
                                            rasterize_polygons)
from collisim.statics.map_chains import FREE_SIDE_OF_OPENCV_TRACE, STAIRS, free_side

DISC = (5.1, 4.7, 3.3)   # centre x, y and radius, inside a 10 x 10 world


@pytest.fixture(scope="module")
def shapely():
    return pytest.importorskip("shapely")


def image_of(solid_rows_up: np.ndarray) -> np.ndarray:
    """The uint8 image (0 solid, 255 free, row 0 at the top) of a mask whose row 0 is the lowest y."""
    return np.where(solid_rows_up[::-1], 0, 255).astype(np.uint8)


def disc_map(cell: float, simplify: float = 0.25) -> CollisionMap:
    n = int(round(10.0 / cell))
    return CollisionMap.from_image(rasterize_polygons([], (n, n), cell=cell, circles=[DISC]), cell=cell,
                                   simplify=simplify)


def blob_image(rng, size=48) -> np.ndarray:
    """Discs and rectangles, some solid, some cut out: holes, islands, concave corners."""
    image = np.full((size, size), 255, np.uint8)
    for _ in range(5):
        centre = tuple(int(v) for v in rng.integers(0, size, 2))
        cv2.circle(image, centre, int(rng.integers(2, size // 5)), 0, -1)
    for _ in range(4):
        (x, y), (w, h) = rng.integers(0, size - 4, 2), rng.integers(1, size // 3, 2)
        image[y:y + h, x:x + w] = 255 if rng.random() < 0.4 else 0
    return image


def pixel_union(shapely, m: CollisionMap):
    """The solid region as shapely geometry: the union of the solid pixel squares (row runs)."""
    x0, y0 = m.origin
    boxes = []
    for i, row in enumerate(m.solid):
        edges = np.flatnonzero(np.diff(np.concatenate([[0], row.astype(np.int8), [0]])))
        for a, b in zip(edges[::2], edges[1::2]):
            boxes.append(shapely.box(x0 + a * m.cell, y0 + i * m.cell, x0 + b * m.cell, y0 + (i + 1) * m.cell))
    return shapely.unary_union(boxes)


def chain_region(shapely, m: CollisionMap):
    """The region the chains enclose, by the even-odd rule (a hole's chain cuts it out)."""
    return reduce(shapely.symmetric_difference, [shapely.Polygon(chain) for chain in m.chains])


def chain_lines(shapely, m: CollisionMap):
    return shapely.MultiLineString([np.vstack([chain, chain[:1]]) for chain in m.chains])


def solid_at(m: CollisionMap, points: np.ndarray) -> np.ndarray:
    """Is each point's pixel solid?"""
    j, i = np.floor((points - m.origin) / m.cell).astype(int).T
    return m.solid[i, j]


def one_line(error) -> str:
    message = str(error.value)
    assert message and "\n" not in message, message
    assert "Traceback" not in message and "cv::" not in message and "reshape" not in message, message
    return message


# ---------------------------------------------------------------- the distance field

def test_disc_distance_is_within_the_pixelation_bound_and_shrinks_with_the_cell(rng):
    # The bound, in cells h. The solid pixels are those whose centres lie in the disc D, so the
    # boundary of their union S lies within sqrt(2)/2 h of the circle and the circle within
    # sqrt(2)/2 h of it: |sd_S - sd_D| <= 0.71 h. At a pixel centre the grid is the distance to the
    # nearest opposite pixel centre less h/2, which overestimates the distance to that pixel's
    # square by at most (sqrt(2) - 1)/2 h = 0.21 h: every sample is within 0.92 h of |p - c| - R.
    # Bilinear interpolation reproduces linear functions, so between samples it adds only the
    # curvature term h^2 / (4 rho), rho >= (2 - sqrt(2)) h the distance from the sample square to c
    # for points at least 2 h from the centre: 0.43 h. Total < 1.35 h <= 1.5 h.
    cx, cy, r = DISC
    errors = []
    for cell in (0.25, 0.0625):
        m = disc_map(cell)
        points = rng.uniform(1.0, 9.0, (4000, 2))
        rho = np.hypot(points[:, 0] - cx, points[:, 1] - cy)
        points, rho = points[rho >= 2 * cell], rho[rho >= 2 * cell]
        exact = rho - r
        assert (exact < 0).sum() > 500 and (exact > 0).sum() > 500
        error = np.abs(m.distance(points) - exact).max()
        assert error <= 1.5 * cell
        errors.append(error)
    assert errors[1] < errors[0] / 2


def rectangle_distance(points, lo, hi):
    """Exact signed distance to the axis-aligned rectangle [lo, hi] (negative inside)."""
    outside = np.maximum(np.maximum(lo - points, points - hi), 0.0)
    depth = np.minimum(points - lo, hi - points).min(axis=1)
    inside = np.all((points > lo) & (points < hi), axis=1)
    return np.where(inside, -depth, np.hypot(outside[:, 0], outside[:, 1]))


RECT_CELL, RECT_ORIGIN = 0.1, np.array([-1.5, 2.0])


@pytest.fixture(scope="module")
def rectangle():
    """30 x 40 pixels, solid rows 8..19 (from the bottom) and columns 10..29: (map, lo, hi)."""
    solid = np.zeros((30, 40), bool)
    solid[8:20, 10:30] = True
    m = CollisionMap.from_image(image_of(solid), cell=RECT_CELL, origin=RECT_ORIGIN)
    return m, RECT_ORIGIN + RECT_CELL * np.array([10, 8]), RECT_ORIGIN + RECT_CELL * np.array([30, 20])


def test_rectangle_distance_is_exact_at_pixel_centres_where_the_nearest_solid_is_straight_across(rectangle):
    m, lo, hi = rectangle
    rows, cols = np.mgrid[0:30, 0:40]
    centres = np.column_stack([(m.origin[0] + (cols + 0.5) * m.cell).ravel(),
                               (m.origin[1] + (rows + 0.5) * m.cell).ravel()])
    # corner zones (outside, diagonal from the rectangle) have a corner, not an edge, nearest
    straight = ((rows >= 8) & (rows < 20)) | ((cols >= 10) & (cols < 30))
    exact = rectangle_distance(centres, lo, hi)
    assert np.abs(m.distance(centres) - exact)[straight.ravel()].max() < 1e-12
    assert np.array_equal(m.distance(centres) < 0, m.solid.ravel())


@pytest.mark.parametrize("side", ["left", "right", "bottom", "top"])
def test_rectangle_distance_and_normal_are_exact_along_each_straight_edge(rectangle, rng, side):
    m, lo, hi = rectangle
    h = m.cell
    axis, outward = {"left": (0, -1), "right": (0, 1), "bottom": (1, -1), "top": (1, 1)}[side]
    edge = hi[axis] if outward > 0 else lo[axis]
    # within 3 cells of the edge across it, and along it well inside the edge's span, so every
    # sample the bilinear cell uses has this edge as its nearest
    along = rng.uniform(lo[1 - axis] + 4 * h, hi[1 - axis] - 4 * h, 500)
    across = edge + rng.uniform(-3 * h, 3 * h, 500)
    points = np.empty((500, 2))
    points[:, axis], points[:, 1 - axis] = across, along
    distances, normals = m.sample(points)
    assert np.abs(distances - outward * (across - edge)).max() < 1e-12
    expected = np.zeros(2)
    expected[axis] = outward
    assert np.all(normals == expected)   # exactly axis-aligned


def test_half_plane_is_exact_everywhere_including_solid_touching_the_image_border(rng):
    # Only pixels inside the image count, so the solid's depth is measured to the edge alone.
    solid = np.zeros((25, 40), bool)
    solid[:, :17] = True
    m = CollisionMap.from_image(image_of(solid), cell=0.25, origin=(3.0, -1.0))
    edge = 3.0 + 17 * 0.25
    points = np.column_stack([rng.uniform(3.125, 12.875, 1000), rng.uniform(-3.0, 8.0, 1000)])
    distances, normals = m.sample(points)
    assert np.abs(distances - (points[:, 0] - edge)).max() < 1e-12
    assert np.all(normals == [1.0, 0.0])


def test_distance_is_negative_exactly_in_solid_pixels_away_from_their_edges(shapely, rng):
    # The bilinear zero level rounds a convex pixel corner off (a corner pixel has -h/2 at its
    # centre but +h/2, +h/2 and +0.91 h at its free neighbours): within about 0.23 pixel of the
    # two edges the sign can differ. Points farther from every solid-free edge must agree.
    for _ in range(3):
        m = CollisionMap.from_image(blob_image(rng), cell=0.5, origin=(-4.0, 7.0))
        x0, y0, x1, y1 = m.bounds
        points = rng.uniform((x0, y0), (x1, y1), (20000, 2))
        margin = shapely.distance(pixel_union(shapely, m).boundary, shapely.points(points))
        points = points[margin > 0.3 * m.cell]
        assert np.array_equal(m.distance(points) < 0, solid_at(m, points))


def test_normal_points_out_of_a_disc_and_along_the_field():
    m = disc_map(0.125)
    cx, cy, r = DISC
    angles = np.linspace(0, 2 * np.pi, 200, endpoint=False)
    points = np.column_stack([cx + (r + 1.0) * np.cos(angles), cy + (r + 1.0) * np.sin(angles)])
    normals = m.normal(points)
    assert np.allclose(np.hypot(normals[:, 0], normals[:, 1]), 1.0)
    radial = np.column_stack([np.cos(angles), np.sin(angles)])
    assert np.min(np.sum(normals * radial, axis=1)) > np.cos(np.radians(30))
    # stepping along the normal increases the distance (it points toward free space)
    assert np.all(m.distance(points + 0.05 * normals) > m.distance(points))


def test_flat_field_falls_back_to_central_differences_then_to_zero():
    # A free corridor two pixels high: between its rows the bilinear field is flat; the grid's
    # central differences at the nearer (lower) row point up, away from the lower wall.
    solid = np.ones((6, 10), bool)
    solid[2:4, :] = False
    m = CollisionMap.from_image(image_of(solid))
    assert np.array_equal(m.normal([4.3, 2.9]), [0.0, 1.0])
    assert np.array_equal(m.normal([4.3, 3.1]), [0.0, -1.0])
    # A checkerboard's pixel corner: a saddle, and the samples around it are symmetric.
    checker = (np.add.outer(np.arange(8), np.arange(8)) % 2).astype(bool)
    m = CollisionMap.from_image(image_of(checker))
    assert np.array_equal(m.normal([4.0, 4.0]), [0.0, 0.0])


def test_outside_the_image_the_border_samples_repeat():
    m = disc_map(0.25)
    inside = m.sample(np.array([[0.125, 3.0], [9.875, 8.0], [4.0, 0.125]]))
    outside = m.sample(np.array([[-50.0, 3.0], [1e9, 8.0], [4.0, -np.inf]]))
    assert np.array_equal(inside[0], outside[0])


def test_vectorised_queries_accept_one_point_and_refuse_bad_shapes():
    m = disc_map(0.25)
    d, n = m.sample([1.0, 1.0])
    assert isinstance(d, float) and n.shape == (2,)
    assert m.distance(np.array([[1.0, 1.0]])).shape == (1,) and m.normal(np.zeros((0, 2))).shape == (0, 2)
    for bad in ([1.0, 2.0, 3.0], np.zeros((3, 3)), [[np.nan, 1.0]], "ab"):
        with pytest.raises(ValueError) as error:
            m.distance(bad)
        one_line(error)


@njit
def _through_numba(field, x, y):
    d, nx, ny = map_sample(field, x, y)
    return d, nx, ny, has_map(field)


def test_map_sample_is_callable_from_compiled_code_with_or_without_a_map():
    m = disc_map(0.25)
    field = m.field
    assert isinstance(field, MapField) and field.distance.flags.c_contiguous and field.distance.dtype == np.float64
    assert (field.x0, field.y0, field.cell, field.ny, field.nx) == (0.0, 0.0, 0.25, 40, 40)
    d, nx, ny, present = _through_numba(field, 2.0, 7.5)
    assert present and (d, nx, ny) == (m.distance([2.0, 7.5]), *m.normal([2.0, 7.5]))
    empty = no_map_field()
    assert _through_numba(empty, 2.0, 7.5) == (np.inf, 0.0, 0.0, False)
    assert not has_map(empty) and has_map(field)


# ---------------------------------------------------------------- the chains

def test_rectangle_chain_is_its_pixel_edge_boundary_exactly(shapely, rectangle):
    m, lo, hi = rectangle
    assert len(m.chains) == 1
    chain = m.chains[0]
    corners = {(lo[0], lo[1]), (lo[0], hi[1]), (hi[0], hi[1]), (hi[0], lo[1])}
    assert len(chain) == 4 and set(map(tuple, chain)) == corners
    assert shapely.Polygon(chain).equals(pixel_union(shapely, m))
    assert np.array_equal(m.segments, np.column_stack([chain, np.roll(chain, -1, axis=0)]))


@pytest.mark.parametrize("name", ["pixel", "line", "T", "L", "room", "border", "plus"])
def test_pixel_art_chains_follow_the_pixel_edges_exactly(shapely, name):
    image = np.full((14, 14), 255, np.uint8)
    if name == "pixel":
        image[5, 5] = 0
    elif name == "line":
        image[5, 2:9] = 0
    elif name == "T":
        image[2, 1:8], image[2:8, 4] = 0, 0
    elif name == "L":
        image[5:8, 2:9], image[2:10, 2:4] = 0, 0
    elif name == "room":        # a square room: the hole's corners stay square
        image[2:12, 2:12], image[4:9, 5:10] = 0, 255
    elif name == "border":      # solid along three image edges: closed along the border
        image[:4, :], image[:, :2], image[:, -3:] = 0, 0, 0
    else:
        image[6, 2:11], image[2:11, 6] = 0, 0
    m = CollisionMap.from_image(image, cell=0.5, origin=(1.0, -2.0))
    assert chain_region(shapely, m).equals(pixel_union(shapely, m))


def test_disc_chain_matches_the_solid_pixels(shapely):
    for simplify in (0.25, 1.0):
        m = disc_map(0.0625, simplify=simplify)
        assert len(m.chains) == 1
        polygon, pixels = shapely.Polygon(m.chains[0]), pixel_union(shapely, m)
        assert abs(polygon.area - pixels.area) < 0.02 * pixels.area
        gap = shapely.hausdorff_distance(polygon.exterior, pixels.exterior, densify=0.05)
        assert gap <= (max(simplify, STAIRS) + 0.5 ** 0.5) * m.cell + 1e-9   # a disc's edge is staircases
        assert len(m.chains[0]) < 4 * m.shape[0]   # simplified: far fewer vertices than boundary pixels


def test_ring_gives_an_outer_chain_and_a_hole_chain_offset_toward_the_hole(shapely):
    cell, (cx, cy) = 0.0625, (5.0, 5.0)
    image = rasterize_polygons([], (160, 160), cell=cell, circles=[(cx, cy, 4.0)])
    hole = rasterize_polygons([], (160, 160), cell=cell, circles=[(cx, cy, 2.5)]) == 0
    image[hole] = 255
    m = CollisionMap.from_image(image, cell=cell)
    assert len(m.chains) == 2
    radii = [np.hypot(c[:, 0] - cx, c[:, 1] - cy).mean() for c in m.chains]
    outer, inner = (m.chains[k] for k in np.argsort(radii)[::-1])
    hole_area = hole.sum() * cell ** 2
    # moved toward the hole, the chain encloses the hole's pixels; moved the wrong way (into the
    # solid, or left on the pixel centres) it would be a pixel too wide or too narrow: 10 % off
    assert abs(shapely.Polygon(inner).area - hole_area) < 0.02 * hole_area
    assert abs(shapely.Polygon(outer).area - np.pi * 4.0 ** 2) < 0.02 * np.pi * 4.0 ** 2
    # the staircases straightened stray from the pixels by 0.3 of a pixel on average; a chain left
    # on the pixel centres strays by half a pixel all round, one moved the wrong way by a pixel
    perimeter = 2.0 * np.pi * (4.0 + 2.5)
    assert chain_region(shapely, m).symmetric_difference(pixel_union(shapely, m)).area < 0.4 * cell * perimeter


def test_opencv_traces_with_free_space_on_the_left_as_the_chains_assume(rng):
    # free_side decides from the signed area; the fallback for zero-area contours (one-pixel
    # lines) is OpenCV's convention, which must agree with the area wherever there is one.
    checked = 0
    for _ in range(10):
        padded = np.pad(blob_image(rng) == 0, 1).astype(np.uint8)
        contours, hierarchy = cv2.findContours(padded, cv2.RETR_CCOMP, cv2.CHAIN_APPROX_NONE)
        for contour, links in zip(contours, hierarchy[0]):
            assert free_side(contour[:, 0, :], hole=links[3] >= 0) == FREE_SIDE_OF_OPENCV_TRACE
            checked += 1
    assert checked > 30


def test_chains_stay_within_half_a_pixel_plus_the_staircases_tolerance_of_any_pixel_region(shapely, rng):
    # (simplify, 0.25, is below STAIRS: a straightened staircase strays farthest, STAIRS from its
    # pixels' centres and so STAIRS + 1/sqrt(2) from their squares' corners)
    for size, solid_fraction in ((40, None), (30, 0.3), (30, 0.6)):
        image = blob_image(rng, size) if solid_fraction is None else \
            np.where(rng.random((size, size)) < solid_fraction, 0, 255).astype(np.uint8)
        m = CollisionMap.from_image(image, cell=0.5)
        gap = shapely.hausdorff_distance(chain_lines(shapely, m), pixel_union(shapely, m).boundary, densify=0.05)
        assert gap <= (STAIRS + 0.5 ** 0.5) * m.cell + 1e-9


@pytest.mark.parametrize("thickness", [1, 2, 3])
def test_a_thin_slanted_wall_is_one_simple_outline_along_it(shapely, thickness):
    # a painted slope is a staircase of pixels: its outline is straightened (ccd slides down it
    # rather than hopping from step to step), but the two sides of a thin wall must not cross
    for degrees in range(5, 90, 10):
        image = np.full((80, 80), 255, np.uint8)
        end = (int(round(5 + 70 * np.cos(np.radians(degrees)))), int(round(75 - 70 * np.sin(np.radians(degrees)))))
        cv2.line(image, (5, 75), end, 0, thickness)
        m = CollisionMap.from_image(image, cell=0.5)
        assert len(m.chains) == 1
        ring = shapely.LinearRing(m.chains[0])
        assert ring.is_simple or thickness == 1, degrees   # a one-pixel line's outline may touch itself
        gap = shapely.hausdorff_distance(ring, pixel_union(shapely, m).boundary, densify=0.05)
        assert gap <= (STAIRS + 0.5 ** 0.5) * m.cell + 1e-9, degrees
        assert len(m.chains[0]) <= 12, degrees   # straight sides, not a staircase of corners


# ---------------------------------------------------------------- images, conventions, determinism

def test_image_rows_are_flipped_and_origin_is_the_lower_left_corner(shapely):
    image = np.full((4, 6), 255, np.uint8)
    image[0, 0] = 0                                      # top-left pixel of the image
    m = CollisionMap.from_image(image, cell=2.0, origin=(10.0, 20.0))
    assert m.shape == (4, 6) and m.bounds == (10.0, 20.0, 22.0, 28.0)
    assert m.solid[3, 0] and m.solid.sum() == 1          # row 0 of every grid is the lowest y
    assert shapely.Polygon(m.chains[0]).equals(shapely.box(10.0, 26.0, 12.0, 28.0))
    assert m.distance([11.0, 27.0]) == -1.0 and m.distance([13.0, 27.0]) == 1.0
    assert "\n" not in repr(m) and repr(m).startswith("CollisionMap(6x4 pixels")
    assert collisim.CollisionMap is CollisionMap


def test_files_arrays_channels_and_alpha_agree(tmp_path, rng):
    gray = blob_image(rng, 32)
    rgb = np.stack([gray, np.full_like(gray, 200), gray], axis=2)   # mean stays dark where gray is 0
    expected = CollisionMap.from_image(gray).solid
    cv2.imwrite(str(tmp_path / "gray.png"), gray)
    cv2.imwrite(str(tmp_path / "colour.png"), rgb[:, :, ::-1])
    cv2.imwrite(str(tmp_path / "deep.png"), gray.astype(np.uint16) * 257)
    assert np.array_equal(CollisionMap.from_image(tmp_path / "gray.png").solid, expected)
    assert np.array_equal(CollisionMap.from_image(str(tmp_path / "deep.png")).solid, expected)
    assert np.array_equal(CollisionMap.from_image(gray / 255.0).solid, expected)
    assert np.array_equal(CollisionMap.from_image(tmp_path / "colour.png", channel="r").solid, expected)
    assert np.array_equal(CollisionMap.from_image(rgb, channel=0).solid, expected)
    assert np.array_equal(CollisionMap.from_image(rgb, threshold=0.6).solid, expected)
    # RGBA: a fully transparent pixel is free whatever its colour
    rgba = np.concatenate([np.zeros_like(rgb), np.where(gray == 0, 255, 0)[:, :, None].astype(np.uint8)], axis=2)
    cv2.imwrite(str(tmp_path / "alpha.png"), rgba[:, :, [2, 1, 0, 3]])
    assert np.array_equal(CollisionMap.from_image(tmp_path / "alpha.png").solid, expected)
    assert np.array_equal(CollisionMap.from_image(rgba, channel="a").solid, ~expected)   # the alpha itself


def test_same_image_gives_the_same_bytes(rng):
    image = blob_image(rng, 64)
    a, b = CollisionMap.from_image(image, cell=0.3), CollisionMap.from_image(image.copy(), cell=0.3)
    for name in ("solid", "distance_grid", "origin", "segments"):
        assert getattr(a, name).tobytes() == getattr(b, name).tobytes()
    assert len(a.chains) == len(b.chains) and all(x.tobytes() == y.tobytes() for x, y in zip(a.chains, b.chains))


# ---------------------------------------------------------------- the map file

def same_map(a: CollisionMap, b: CollisionMap) -> bool:
    arrays = [(getattr(a, name), getattr(b, name)) for name in ("solid", "distance_grid", "origin", "segments")]
    arrays += list(zip(a.chains, b.chains))
    return (a.cell == b.cell and len(a.chains) == len(b.chains)
            and all(x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes() for x, y in arrays))


def test_save_and_load_give_the_same_arrays(tmp_path, rng):
    m = CollisionMap.from_image(blob_image(rng), cell=0.2, origin=(-1.0, 4.5))
    path = m.save(tmp_path / "level.npz")
    loaded = CollisionMap.load(path)
    assert same_map(m, loaded)
    assert loaded.field.distance.flags.c_contiguous
    points = rng.uniform((-1.0, 4.5), (8.6, 14.1), (100, 2))
    assert np.array_equal(loaded.distance(points), m.distance(points))
    assert [p.name for p in tmp_path.iterdir()] == ["level.npz"]   # no temporary left


def test_load_refuses_other_versions_and_foreign_or_broken_files(tmp_path, rng):
    m = CollisionMap.from_image(blob_image(rng, 24))
    good = m.save(tmp_path / "good.npz")
    with np.load(good) as data:
        arrays = dict(data)
    np.savez(tmp_path / "future.npz", **{**arrays, "map_format": np.array(MAP_FORMAT + 1)})
    with pytest.raises(ValueError, match=f"format version {MAP_FORMAT + 1}") as error:
        CollisionMap.load(tmp_path / "future.npz")
    one_line(error)
    (tmp_path / "truncated.npz").write_bytes(good.read_bytes()[: good.stat().st_size // 2])
    (tmp_path / "garbage.npz").write_bytes(rng.bytes(3000))
    np.savez(tmp_path / "trajectory.npz", meta=np.array("{}"), frame_times=np.zeros(3))
    np.save(tmp_path / "array.npy", np.zeros(3))
    np.savez(tmp_path / "shapes.npz", **{**arrays, "distance": arrays["distance"][1:]})
    for name in ("truncated.npz", "garbage.npz", "trajectory.npz", "array.npy", "shapes.npz", "missing.npz"):
        with pytest.raises(ValueError, match="cannot read collision map") as error:
            CollisionMap.load(tmp_path / name)
        one_line(error)


def test_a_failed_save_leaves_nothing_behind(tmp_path, rng, monkeypatch):
    m = CollisionMap.from_image(blob_image(rng, 24))
    with pytest.raises(ValueError, match="cannot write collision map") as error:
        m.save(tmp_path / "no such folder" / "level.npz")
    one_line(error)
    (tmp_path / "taken").mkdir()
    with pytest.raises(ValueError, match="cannot write collision map"):
        m.save(tmp_path / "taken")                      # a folder is in the way of the rename

    def interrupted(*args, **kwargs):
        raise KeyboardInterrupt
    monkeypatch.setattr(np, "savez_compressed", interrupted)
    with pytest.raises(KeyboardInterrupt):
        m.save(tmp_path / "level.npz")
    assert [p.name for p in tmp_path.iterdir()] == ["taken"] and not any((tmp_path / "taken").iterdir())


# ---------------------------------------------------------------- bad input

def _write(tmp_path, name, data: bytes):
    (tmp_path / name).write_bytes(data)
    return tmp_path / name


GRAY = np.where(np.arange(64).reshape(8, 8) % 3 == 0, 0, 255).astype(np.uint8)
RGB = np.stack([GRAY] * 3, axis=2)

BAD_INPUTS = {
    "missing file": (lambda tmp: tmp / "missing.png", {}, "not found"),
    "not an image": (lambda tmp: _write(tmp, "notes.png", b"just some text"), {}, "not an image"),
    "a folder": (lambda tmp: tmp, {}, "not a file"),
    "no solid pixel": (lambda tmp: np.full((8, 8), 255, np.uint8), {}, "no solid pixel"),
    "all solid": (lambda tmp: np.zeros((8, 8), np.uint8), {}, "solid everywhere"),
    "empty array": (lambda tmp: np.zeros((0, 8), np.uint8), {}, "empty"),
    "one dimension": (lambda tmp: np.zeros(8, np.uint8), {}, "shape"),
    "two channels": (lambda tmp: np.zeros((8, 8, 2), np.uint8), {}, "shape"),
    "int64 image": (lambda tmp: GRAY.astype(np.int64), {}, "uint8"),
    "bool image": (lambda tmp: GRAY > 0, {}, "uint8"),
    "float above 1": (lambda tmp: GRAY.astype(float), {}, "[0, 1]"),
    "float NaN": (lambda tmp: np.full((8, 8), np.nan), {}, "[0, 1]"),
    "a list": (lambda tmp: GRAY.tolist(), {}, "numpy array"),
    "cell zero": (lambda tmp: GRAY, {"cell": 0.0}, "cell"),
    "cell negative": (lambda tmp: GRAY, {"cell": -1.0}, "cell"),
    "cell inf": (lambda tmp: GRAY, {"cell": np.inf}, "cell"),
    "cell NaN": (lambda tmp: GRAY, {"cell": np.nan}, "cell"),
    "cell text": (lambda tmp: GRAY, {"cell": "1"}, "cell"),
    "origin NaN": (lambda tmp: GRAY, {"origin": (np.nan, 0.0)}, "origin"),
    "origin three": (lambda tmp: GRAY, {"origin": (1.0, 2.0, 3.0)}, "origin"),
    "origin text": (lambda tmp: GRAY, {"origin": "ab"}, "origin"),
    "threshold zero": (lambda tmp: GRAY, {"threshold": 0.0}, "threshold"),
    "threshold above 1": (lambda tmp: GRAY, {"threshold": 1.5}, "threshold"),
    "threshold NaN": (lambda tmp: GRAY, {"threshold": np.nan}, "threshold"),
    "simplify negative": (lambda tmp: GRAY, {"simplify": -0.5}, "simplify"),
    "channel name": (lambda tmp: RGB, {"channel": "x"}, "channel"),
    "channel index": (lambda tmp: RGB, {"channel": 3}, "channel"),
    "channel of gray": (lambda tmp: GRAY, {"channel": "r"}, "channel"),
    "channel bool": (lambda tmp: RGB, {"channel": True}, "channel"),
    "alpha of RGB": (lambda tmp: RGB, {"channel": "a"}, "channel"),
}


@pytest.mark.parametrize("case", BAD_INPUTS)
def test_bad_input_is_one_plain_line_and_writes_nothing(tmp_path, case):
    make, options, words = BAD_INPUTS[case]
    image = make(tmp_path)
    before = sorted(tmp_path.iterdir())
    with pytest.raises(ValueError) as error:
        CollisionMap.from_image(image, **options)
    assert words in one_line(error)
    assert sorted(tmp_path.iterdir()) == before


# ---------------------------------------------------------------- rasterize_polygons

def random_polygon(rng, centre, radius, corners):
    """A simple (star-shaped) polygon: corners at sorted random angles and random radii."""
    angles = np.sort(rng.uniform(0, 2 * np.pi, corners))
    radii = rng.uniform(0.3, 1.0, corners) * radius
    return np.column_stack([centre[0] + radii * np.cos(angles), centre[1] + radii * np.sin(angles)])


def test_rasterize_marks_exactly_the_pixels_whose_centres_are_inside(shapely, rng):
    cell, origin, (height, width) = 0.137, np.array([-2.3, 1.1]), (80, 100)
    for _ in range(5):
        polygons = [random_polygon(rng, rng.uniform(origin, origin + cell * np.array([width, height])), 3.0,
                                   int(rng.integers(3, 12))) for _ in range(3)]
        circles = [(*rng.uniform(origin, origin + 10.0), rng.uniform(0.2, 2.0)) for _ in range(2)]
        image = rasterize_polygons(polygons, (height, width), cell=cell, origin=origin, circles=circles)
        assert image.dtype == np.uint8 and image.shape == (height, width) and set(np.unique(image)) <= {0, 255}
        rows, cols = np.mgrid[0:height, 0:width]
        x, y = origin[0] + (cols + 0.5) * cell, origin[1] + (height - 1 - rows + 0.5) * cell   # row 0 at the top
        inside = reduce(np.logical_or, [shapely.contains_xy(shapely.Polygon(p), x, y) for p in polygons])
        for cx, cy, r in circles:
            inside |= (x - cx) ** 2 + (y - cy) ** 2 <= r * r
        assert np.array_equal(image == 0, inside)


def test_rasterize_refuses_bad_shapes_in_one_line():
    for args, options in ((([[(0, 0), (1, 1)]], (4, 4)), {}), (([], (0, 4)), {}), (([], (4.5, 4)), {}),
                          (([[(0, 0), (1, np.nan), (1, 0)]], (4, 4)), {}), (([], (4, 4)), {"circles": [(1, 1, -1)]}),
                          (([], (4, 4)), {"cell": 0}), (([], (4, 4)), {"circles": [(1, 2)]})):
        with pytest.raises(ValueError) as error:
            rasterize_polygons(*args, **options)
        one_line(error)
