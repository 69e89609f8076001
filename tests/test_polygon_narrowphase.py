"""The polygon narrow phase (narrowphase/polygons.py) against shapely, on 10 000 seeded pairs.

Independent references:
- overlap: shapely `intersects` (and `touches` for pairs built to touch exactly);
- penetration depth of two convex shapes: the distance from the origin to the boundary of
  their Minkowski difference, the convex hull of every a_i - b_j;
- polygon–circle depth: r minus the signed distance from the centre to the polygon;
- when apart: shapely `distance`.
The normal is checked by moving: b moved by depth along it touches a (the point depth·n lies
on the Minkowski difference's boundary), and moved by a little less still overlaps. The
points are checked against their documented place: point ± (depth/2)·n on a's and b's surface.
"""
import numpy as np
import pytest
from shapely import affinity
from shapely.geometry import LineString, MultiPoint, Point, Polygon

from collisim.narrowphase.polygons import (box_wall_halfplane, polygon_circle, polygon_circle_touch,
                                           polygon_halfplane, polygon_polygon, polygon_segment,
                                           polygons_touch)
from collisim.shapes import box

SEED = 20240611


# --- data ---------------------------------------------------------------------------------

def ellipse_polygons(rng, count, size=(0.2, 2.0), centre=(0.0, 0.0), spread=0.0):
    """count convex counter-clockwise polygons of 3 to 8 vertices: points at sorted angles on a
    rotated ellipse (any k points of an ellipse are in convex position), vectorised."""
    k = rng.integers(3, 9, count)
    slot = (np.arange(8) + rng.uniform(0.0, 0.8, (count, 8))) * 2 * np.pi / k[:, None]
    angles = slot + rng.uniform(0, 2 * np.pi, (count, 1))
    radii = np.exp(rng.uniform(*np.log(size), (count, 2)))
    turn = rng.uniform(0, 2 * np.pi, count)
    x, y = radii[:, :1] * np.cos(angles), radii[:, 1:] * np.sin(angles)
    c, s = np.cos(turn)[:, None], np.sin(turn)[:, None]
    moved = np.asarray(centre) + rng.uniform(-spread, spread, (count, 2))
    points = np.stack([c * x - s * y + moved[:, :1], s * x + c * y + moved[:, 1:]], axis=2)
    return [points[i, :k[i]] for i in range(count)]


def integer_polygons(rng, count):
    """count convex polygons with integer vertices (hulls of random integer points)."""
    from scipy.spatial import ConvexHull
    out = []
    while len(out) < count:
        points = rng.integers(-12, 13, (rng.integers(4, 10), 2)).astype(float)
        if np.linalg.matrix_rank(points - points[0]) == 2:
            out.append(points[ConvexHull(points).vertices])
    return out


def rotated(vertices, angle, about=(0.0, 0.0)):
    c, s = np.cos(angle), np.sin(angle)
    return (vertices - about) @ np.array([[c, s], [-s, c]]) + about


def size(vertices):
    return np.ptp(vertices, axis=0).max()


@pytest.fixture(scope="module")
def polygon_pairs():
    """(category, a, b) for polygon–polygon: 6000 pairs, about half overlapping."""
    rng = np.random.default_rng(SEED)
    pairs = []
    a, b = ellipse_polygons(rng, 3000), ellipse_polygons(rng, 3000, spread=1.8)
    pairs += [("random", p, q) for p, q in zip(a, b)]
    big, small = ellipse_polygons(rng, 400, (1.0, 3.0)), ellipse_polygons(rng, 400, (0.05, 0.4))
    pairs += [("inside", p, q - q.mean(0) + p.mean(0) + rng.uniform(-0.3, 0.3, 2)) for p, q in zip(big, small)]
    huge, tiny = ellipse_polygons(rng, 400, (300.0, 1000.0)), ellipse_polygons(rng, 400, (1e-3, 3e-3))
    for p, q in zip(huge, tiny):                     # tiny ones near the huge one's boundary
        i = rng.integers(len(p))
        edge_point = p[i] + rng.uniform(0, 1) * (p[(i + 1) % len(p)] - p[i])
        pairs.append(("huge-tiny", p, q + edge_point + rng.uniform(-4e-3, 4e-3, 2)))
        pairs.append(("tiny-huge", pairs[-1][2], p))
    pairs += [("identical", p, p.copy()) for p in ellipse_polygons(rng, 200)]
    for _ in range(400):                             # faces within 1e-5 rad of parallel
        w, h = rng.uniform(0.5, 3.0, 2)
        p, q = box(w, h), box(rng.uniform(0.2, w), rng.uniform(0.2, 2.0))
        tilt = rng.choice([-1, 1]) * 10 ** rng.uniform(-12, -5)
        lift = (h + q[2, 1] - q[0, 1]) / 2 - rng.uniform(-1e-3, 1e-2)
        pairs.append(("parallel", p, rotated(q, tilt) + (rng.uniform(-0.2, 0.2) * w, lift)))
    far = np.array([1e6, -1e6])
    a, b = ellipse_polygons(rng, 400), ellipse_polygons(rng, 400, spread=2.0)
    pairs += [("far", p + far, q + far) for p, q in zip(a, b)]
    return pairs


@pytest.fixture(scope="module")
def touching_pairs():
    """(category, a, b) with integer or half-integer vertices, built to touch exactly."""
    rng = np.random.default_rng(SEED + 1)
    pairs = []
    for p in integer_polygons(rng, 500):
        k = len(p)
        shift = rng.integers(-50, 50, 2).astype(float)
        if k >= 4:                                   # cut along a chord: one shared edge
            j = rng.integers(2, k - 1)
            pairs.append(("shared edge", p[:j + 1] + shift, np.vstack([p[j:], p[:1]]) + shift))
        i = rng.integers(k)
        m = 0.5 * (p[i] + p[(i + 1) % k])            # half-point reflection: the whole edge
        pairs.append(("edge on edge", p, 2 * m - p))
        pairs.append(("vertex on vertex", p, 2 * p[i] - p))
        ex, ey = p[(i + 1) % k] - p[i]
        out = np.array([ey, -ex])                    # integer outward normal of edge i
        wedge = np.array([m, m + out + (ex, ey), m + out - (ex, ey)])
        pairs.append(("vertex on edge", p, wedge[::-1] if _signed_area(wedge) < 0 else wedge))
    return pairs


def _signed_area(v):
    return 0.5 * np.sum(v[:, 0] * np.roll(v[:, 1], -1) - np.roll(v[:, 0], -1) * v[:, 1])


# --- references ------------------------------------------------------------------------------

def minkowski_difference(a, b):
    """The convex hull of every a_i - b_j (a shapely Polygon)."""
    return MultiPoint((a[:, None, :] - b[None, :, :]).reshape(-1, 2)).convex_hull


def tolerance(a, b):
    """1e-9, relative to the smaller shape when it is larger than 1, plus the round-off of
    coordinates far from the origin."""
    return 1e-9 * max(1.0, min(size(a), size(b))) + 1e-15 * max(np.abs(a).max(), np.abs(b).max())


def points_of(m):
    return [(m[3 + 3 * c], np.array(m[4 + 3 * c:6 + 3 * c])) for c in range(m[2])]


def check_pair(a, b, m, shape_a, shape_b, tol):
    """Problems (a list of words) with manifold m of shapes a, b (their vertex arrays and
    shapely shapes), where the depth and normal can be read off the Minkowski difference."""
    problems = []
    nx, ny, count = m[0], m[1], m[2]
    n = np.array([nx, ny])
    if abs(np.hypot(nx, ny) - 1) > 1e-12:
        problems.append("normal not unit")
    if (count > 0) != shape_a.intersects(shape_b):
        problems.append(f"overlap {count > 0} but shapely intersects {shape_a.intersects(shape_b)}")
    if count == 0:
        if abs(-m[3] - shape_a.distance(shape_b)) > tol:
            problems.append(f"separation {-m[3]} != distance {shape_a.distance(shape_b)}")
        moved = affinity.translate(shape_b, *(m[3] * n))     # back along n by the gap
        if moved.distance(shape_a) > tol:
            problems.append("apart normal does not point from a's closest point to b's")
        return problems
    difference = minkowski_difference(a, b)
    depth = difference.exterior.distance(Point(0, 0))
    if abs(m[3] - depth) > tol:
        problems.append(f"depth {m[3]} != penetration {depth}")
    if difference.exterior.distance(Point(*(m[3] * n))) > tol:
        problems.append("moving b by depth along n does not leave them touching")
    depths = [d for d, _ in points_of(m)]
    if depths != sorted(depths, reverse=True) or min(depths) < 0:
        problems.append(f"depths {depths} not deepest first and >= 0")
    for d, p in points_of(m):
        if shape_a.exterior.distance(Point(*(p + 0.5 * d * n))) > tol:
            problems.append("point + depth/2·n is not on a's surface")
        if _surface(shape_b).distance(Point(*(p - 0.5 * d * n))) > tol:
            problems.append("point - depth/2·n is not on b's surface")
    return problems


def _surface(shape):
    return shape if isinstance(shape, LineString) else shape.exterior


def assert_no_problems(cases):
    """cases: (label, problems); fail listing the first few."""
    bad = [(label, problems) for label, problems in cases if problems]
    assert not bad, f"{len(bad)} bad of {len(cases)}; first: {bad[:3]}"


# --- polygon–polygon --------------------------------------------------------------------------

def test_polygon_polygon_against_shapely(polygon_pairs):
    cases = []
    for index, (category, a, b) in enumerate(polygon_pairs):
        m = polygon_polygon(a, b)
        problems = check_pair(a, b, m, Polygon(a), Polygon(b), tolerance(a, b))
        if polygons_touch(a, b) != (m[2] > 0):
            problems.append("polygons_touch disagrees")
        if category == "parallel" and m[2] == 1:
            problems.append("one point for nearly parallel faces")
        cases.append((f"{category} #{index}", problems))
    assert_no_problems(cases)
    overlapping = sum(polygon_polygon(a, b)[2] > 0 for _, a, b in polygon_pairs)
    assert 0.3 < overlapping / len(polygon_pairs) < 0.8


def test_swapping_the_pair_flips_the_normal_and_keeps_the_depth(polygon_pairs):
    cases = []
    for index, (category, a, b) in enumerate(polygon_pairs):
        m, w = polygon_polygon(a, b), polygon_polygon(b, a)
        problems = check_pair(b, a, w, Polygon(b), Polygon(a), tolerance(a, b))
        if (m[2] > 0) != (w[2] > 0) or abs(m[3] - w[3]) > tolerance(a, b):
            problems.append(f"depth {m[3]} swapped {w[3]}")
        # Identical polygons have several equally shallow faces: any is a right normal. Faces
        # whose depths tie within FACE_TOLERANCE keep the first polygon's, so faces a few 1e-9
        # rad from parallel may give normals that differ by that angle.
        if m[2] > 0 and category != "identical" and not np.allclose(m[:2], (-w[0], -w[1]), rtol=0, atol=1e-7):
            problems.append(f"normal {m[:2]} swapped {w[:2]}")
        cases.append((f"{category} #{index}", problems))
    assert_no_problems(cases)


def test_moving_by_the_depth_separates_and_by_less_does_not(polygon_pairs):
    checked = 0
    for category, a, b in polygon_pairs[::6]:
        nx, ny, count, depth = polygon_polygon(a, b)[:4]
        scale = min(size(a), size(b))
        if count == 0 or depth < 1e-4 * scale:
            continue
        shape_a, shape_b = Polygon(a), Polygon(b)
        out = affinity.translate(shape_b, nx * depth, ny * depth)
        assert shape_a.intersection(out).area <= 1e-9 * scale ** 2 and shape_a.distance(out) <= tolerance(a, b)
        short = depth - 1e-5 * scale
        assert shape_a.intersection(affinity.translate(shape_b, nx * short, ny * short)).area > 0
        checked += 1
    assert checked > 300


def test_exactly_touching_pairs_touch_with_depth_zero(touching_pairs):
    cases = []
    for category, a, b in touching_pairs:
        A, B = Polygon(a), Polygon(b)
        assert A.touches(B), category                  # the data is what it claims to be
        m = polygon_polygon(a, b)
        problems = check_pair(a, b, m, A, B, 1e-12)
        if m[2] != (1 if category.startswith("vertex") else 2) or m[3] != 0.0 or m[6] != 0.0:
            problems.append(f"count {m[2]} depths {m[3]}, {m[6]}: not touching exactly")
        if polygon_polygon(b, a)[3] != 0.0 or not polygons_touch(a, b):
            problems.append("not touching exactly when swapped")
        cases.append((category, problems))
    assert_no_problems(cases)
    categories = {category for category, _ in cases}
    assert categories == {"shared edge", "edge on edge", "vertex on vertex", "vertex on edge"}


def test_contact_point_counts():
    square = box(2.0, 2.0)
    flat_on_top = box(1.0, 1.0) + (0.0, 1.4)           # a face inside a face: two points
    m = polygon_polygon(square, flat_on_top)
    assert m[2] == 2 and m[:2] == (0.0, 1.0) and m[3] == pytest.approx(0.1) and m[6] == pytest.approx(0.1)
    assert sorted([m[4], m[7]]) == pytest.approx([-0.5, 0.5]) and m[5] == m[8] == pytest.approx(0.95)
    corner_down = np.array([[0.0, 0.9], [1.0, 1.5], [0.0, 2.1], [-1.0, 1.5]])   # a vertex: one point
    m = polygon_polygon(square, corner_down)
    assert m[2] == 1 and m[3] == pytest.approx(0.1) and m[4:6] == pytest.approx((0.0, 0.95))
    assert polygon_polygon(square, square + (3.0, 4.0))[2:4] == pytest.approx((0, -np.hypot(1.0, 2.0)))


# --- polygon–circle -----------------------------------------------------------------------------

@pytest.fixture(scope="module")
def circle_cases():
    """(category, polygon, cx, cy, r): 2500 cases: random, centres inside, tiny and huge, and
    circles touching a face or a vertex exactly."""
    rng = np.random.default_rng(SEED + 2)
    cases = []
    for p in ellipse_polygons(rng, 1600):
        cases.append(("random", p, *rng.uniform(-2.5, 2.5, 2), np.exp(rng.uniform(np.log(0.01), np.log(2)))))
    for p in ellipse_polygons(rng, 300):
        cases.append(("centre inside", p, *(p.mean(0) + rng.uniform(-0.1, 0.1, 2)), rng.uniform(0.01, 3.0)))
    for p in ellipse_polygons(rng, 200, (300.0, 1000.0)):
        i = rng.integers(len(p))
        cx, cy = p[i] + rng.uniform(-4e-3, 4e-3, 2)
        cases.append(("tiny circle, huge polygon", p, cx, cy, 1e-3))
    for p in ellipse_polygons(rng, 200, (1e-3, 3e-3)):
        cases.append(("huge circle, tiny polygon", p, 1000.0 + rng.uniform(-3e-3, 3e-3), 0.0, 1000.0))
    for _ in range(200):
        x0, y0 = rng.integers(-10, 10, 2).astype(float)
        w, h, s = rng.integers(1, 6, 3).astype(float)
        square = np.array([[x0, y0], [x0 + w, y0], [x0 + w, y0 + h], [x0, y0 + h]])
        cases.append(("touching a face", square, x0 + rng.integers(0, w + 1), y0 + h + s, s))
        cases.append(("touching a vertex", square, x0 + w + 3 * s, y0 + h + 4 * s, 5 * s))
    return cases


def test_polygon_circle_against_shapely(circle_cases):
    cases = []
    for category, a, cx, cy, r in circle_cases:
        m = polygon_circle(a, cx, cy, r)
        shape, centre = Polygon(a), Point(cx, cy)
        signed = -shape.exterior.distance(centre) if shape.contains(centre) else shape.distance(centre)
        tol = 1e-9 * max(1.0, min(size(a), 2 * r)) + 1e-15 * np.abs(a).max()
        n = np.array(m[:2])
        problems = []
        if (m[2] > 0) != (signed <= r) or polygon_circle_touch(a, cx, cy, r) != (m[2] > 0):
            problems.append(f"overlap {m[2] > 0} but signed distance {signed} vs r {r}")
        if abs(m[3] - (r - signed)) > tol:
            problems.append(f"depth {m[3]} != r - signed distance {r - signed}")
        moved = Point(cx + m[3] * n[0], cy + m[3] * n[1])     # circle moved out (or in) by depth
        if abs(shape.exterior.distance(moved) - r) > tol or shape.contains(moved):
            problems.append("moving the circle by depth along n does not leave it touching")
        for d, p in points_of(m):
            if shape.exterior.distance(Point(*(p + 0.5 * d * n))) > tol:
                problems.append("point + depth/2·n is not on the polygon's surface")
            if abs(np.hypot(*(p - 0.5 * d * n - (cx, cy))) - r) > tol:
                problems.append("point - depth/2·n is not on the circle")
        if category.startswith("touching") and (m[2] != 1 or m[3] != 0.0):
            problems.append(f"count {m[2]} depth {m[3]}: not touching exactly")
        cases.append((category, problems))
    assert_no_problems(cases)


def test_polygon_circle_normal_regions():
    square = box(2.0, 2.0)
    m = polygon_circle(square, 2.0, 2.0, 1.5)            # vertex region: along the diagonal
    assert m[2] == 1 and m[:2] == pytest.approx((2 ** -0.5, 2 ** -0.5)) and m[3] == pytest.approx(1.5 - 2 ** 0.5)
    m = polygon_circle(square, 0.5, 1.2, 0.5)            # face region
    assert m[:4] == (0.0, 1.0, 1, pytest.approx(0.3))
    m = polygon_circle(square, 0.2, -0.6, 0.1)           # inside: out through the nearest face
    assert m[:4] == (0.0, -1.0, 1, pytest.approx(0.5))


# --- polygon–segment and half-planes -----------------------------------------------------------

@pytest.fixture(scope="module")
def segment_cases():
    """(category, polygon, segment (2, 2)): 1500 cases."""
    rng = np.random.default_rng(SEED + 3)
    cases = [("random", p, rng.uniform(-2.5, 2.5, (2, 2))) for p in ellipse_polygons(rng, 1200)]
    for p in ellipse_polygons(rng, 150, (0.5, 2.0)):     # short segments wholly inside
        cases.append(("inside", p, p.mean(0) + rng.uniform(-0.1, 0.1, (2, 2))))
    for p in integer_polygons(rng, 150):                 # lying along an edge, exactly
        i = rng.integers(len(p))
        cases.append(("along an edge", p, np.array([p[i], p[(i + 1) % len(p)]])))
    return cases


def test_polygon_segment_against_shapely(segment_cases):
    cases = []
    for category, a, s in segment_cases:
        m = polygon_segment(a, s[0, 0], s[0, 1], s[1, 0], s[1, 1])
        problems = check_pair(a, s, m, Polygon(a), LineString(s), tolerance(a, s))
        if polygons_touch(a, s) != (m[2] > 0):
            problems.append("polygons_touch disagrees")
        if category == "along an edge" and (m[2] != 2 or m[3] != 0.0):
            problems.append(f"count {m[2]} depth {m[3]}: not two touching points")
        cases.append((category, problems))
    assert_no_problems(cases)


def test_a_box_lying_on_a_segment_gets_two_points():
    m = polygon_segment(box(2.0, 1.0) + (0.0, 0.45), -5.0, 0.0, 5.0, 0.0)
    assert m[:4] == (0.0, -1.0, 2, pytest.approx(0.05)) and sorted([m[4], m[7]]) == pytest.approx([-1.0, 1.0])
    m = polygon_segment(box(2.0, 1.0), 3.0, 0.0, 3.0, 0.0)   # a point segment
    assert m[2] == 0 and m[3] == pytest.approx(-2.0)


def test_polygon_halfplane_against_shapely():
    rng = np.random.default_rng(SEED + 4)
    for a in ellipse_polygons(rng, 500):
        angle = rng.uniform(0, 2 * np.pi)
        nx, ny, offset = np.cos(angle), np.sin(angle), rng.uniform(-2.0, 2.0)
        m = polygon_halfplane(a, nx, ny, offset)
        far = 100.0                                       # the solid, as a big shapely polygon
        line = np.array([offset * nx, offset * ny])
        tangent = np.array([-ny, nx]) * far
        solid = Polygon([line - tangent, line + tangent, line + tangent - far * np.array([nx, ny]),
                         line - tangent - far * np.array([nx, ny])])
        shape = Polygon(a)
        assert (m[2] > 0) == shape.intersects(solid) and m[:2] == (-nx, -ny)
        inside = shape.intersection(solid)
        deepest = max(offset - np.dot((nx, ny), v) for v in inside.exterior.coords) if m[2] else -shape.distance(solid)
        assert m[3] == pytest.approx(deepest, abs=1e-12)
        for d, p in points_of(m):
            assert shape.exterior.distance(Point(*(p - 0.5 * d * np.array([nx, ny])))) < 1e-12
            assert abs(np.dot((nx, ny), p + 0.5 * d * np.array([nx, ny])) - offset) < 1e-12


def test_box_walls_as_half_planes():
    walls = np.array([0.0, 0.0, 10.0, 8.0])
    body = box(2.0, 1.0)
    expect = {0: ((0.5, 4.0), (-1.0, 0.0), 0.5), 1: ((9.5, 4.0), (1.0, 0.0), 0.5),
              2: ((5.0, 0.25), (0.0, -1.0), 0.25), 3: ((5.0, 7.75), (0.0, 1.0), 0.25)}
    for wall, (centre, normal, depth) in expect.items():
        m = polygon_halfplane(body + centre, *box_wall_halfplane(walls, wall))
        assert m[:2] == normal and m[2] == 2 and m[3] == pytest.approx(depth) and m[6] == pytest.approx(depth)
        assert polygon_halfplane(body + (5.0, 4.0), *box_wall_halfplane(walls, wall))[2] == 0
