"""Polygon shapes and their geometry: the user-facing checks (shapes.py), mass properties
against pymunk and closed forms, world placement and the bounding shapes (geometry/polygon.py).

About pymunk.moment_for_poly(mass, vertices, offset, radius): its docstring says it "assumes
the polygon center of gravity is at its centroid", but Chipmunk's cpMomentForPoly sums
Σ cross(v2, v1)·(v1·v1 + v1·v2 + v2·v2) about the ORIGIN of the vertex coordinates (after
adding offset), i.e. the moment about the body origin. test_pymunk_moment_is_about_the_origin
shows it: for a polygon whose centroid is not the origin it is I_centroid + m·|c|². So every
comparison below hands pymunk the vertices relative to the centroid.
"""
import numpy as np
import pymunk
import pytest
from scipy.spatial import ConvexHull

from collisim.core.geometry.polygon import (bounding_radius, circle_inertia, edge_normals, oriented_box,
                                       polygon_bounds, polygon_mass_properties, world_vertices)
from collisim.shapes import box, convex_polygon, regular

REL = 1e-12


def random_convex(rng, count, grid=None):
    """count random convex counter-clockwise polygons: the hulls of 3 to 12 gaussian points,
    stretched and moved. With grid, coordinates are multiples of grid (exact when shifted)."""
    polygons = []
    for _ in range(count):
        points = rng.normal(size=(rng.integers(3, 13), 2)) * rng.uniform(0.1, 5.0, 2) + rng.uniform(-5, 5, 2)
        if grid:
            points = np.round(points / grid) * grid
        hull = ConvexHull(points)                      # 2-D hull vertices come counter-clockwise
        polygons.append(points[hull.vertices])
    return polygons


def close(value, expected, rel=REL):
    return abs(value - expected) <= rel * abs(expected)


# --- shapes.py --------------------------------------------------------------------------

def test_box_and_regular_are_centred_and_counter_clockwise():
    assert np.array_equal(box(4.0, 2.0), [[-2, -1], [2, -1], [2, 1], [-2, 1]])
    hexagon = regular(6, 2.0)
    assert hexagon.shape == (6, 2) and np.allclose(hexagon[0], [2.0, 0.0])
    assert np.allclose(np.hypot(*hexagon.T), 2.0) and np.allclose(hexagon.mean(axis=0), 0.0, atol=1e-15)
    for vertices in (box(4.0, 2.0), hexagon, regular(3, 1.0)):
        assert convex_polygon(vertices) == (pytest.approx(vertices), None)


@pytest.mark.parametrize("call, words", [
    (lambda: box(0.0, 1.0), "box width must be a finite number > 0"),
    (lambda: box(1.0, np.inf), "box height must be a finite number > 0"),
    (lambda: regular(2, 1.0), "whole number of sides >= 3"),
    (lambda: regular(5.5, 1.0), "whole number of sides >= 3"),
    (lambda: regular(5, -1.0), "regular polygon radius must be a finite number > 0"),
])
def test_shape_helpers_reject_bad_sizes(call, words):
    with pytest.raises(ValueError, match=words):
        call()


@pytest.mark.parametrize("vertices, words", [
    ([[0, 0], [1, 1]], "body 3's polygon needs at least three distinct vertices, got 2"),
    ([[0, 0], [1, 1], [0, 0], [1, 1]], "needs at least three distinct vertices, got 2"),
    ([[0, 0], [1, 1], [2, 2]], "body 3's polygon has no area: its vertices lie on one line"),
    ([[0, 0], [1, 1e-14], [2, 0]], "has no area: its vertices lie on one line"),
    ([[0, 0], [1, 1], [1, 0], [0, 1]], "body 3's polygon has no area: its edges cross"),
    ([[0, 0], [2, 0], [1, 0.2], [1, 2]], "body 3's polygon is not convex: its vertices turn both ways at vertex 2"),
    ([[0, 0], [2, 0], [2, 2], [2, 1], [0, 2]], "doubles back on itself at vertex 2"),
    (regular(5, 1.0)[[0, 2, 4, 1, 3]], "its edges cross"),
    ([[0, 0], [1, 0], [np.nan, 1]], "body 3's polygon contains NaN or inf"),
    ([[0, 0], [1, 0], [np.inf, 1]], "contains NaN or inf"),
    ([1.0, 2.0, 3.0], r"must have shape \(k, 2\), one \(x, y\) row per vertex, got shape \(3,\)"),
    ([[0, 0, 0], [1, 0, 0], [0, 1, 0]], r"got shape \(3, 3\)"),
    ([["a", "b"], [1, 0], [0, 1]], "must be \\(x, y\\) number pairs"),
])
def test_convex_polygon_rejects_with_one_line(vertices, words):
    with pytest.raises(ValueError, match=words) as caught:
        convex_polygon(vertices, name="body 3's polygon")
    message = str(caught.value)
    assert "\n" not in message and "Traceback" not in message


def test_clockwise_is_reversed_with_a_note_and_vertex_0_kept_first():
    clockwise = [[0, 0], [0, 1], [1, 1], [1, 0]]
    vertices, note = convex_polygon(clockwise, name="body 7's polygon")
    assert note == "body 7's polygon wound clockwise; reversed to counter-clockwise"
    assert np.array_equal(vertices, [[0, 0], [1, 0], [1, 1], [0, 1]]) and vertices.dtype == np.float64
    assert convex_polygon(vertices)[1] is None


def test_repeats_closing_copies_and_straight_vertices_are_dropped():
    vertices, note = convex_polygon([[0, 0], [1, 0], [1, 0], [2, 0], [2, 2], [1, 2.0], [0, 2], [0, 0]])
    assert note is None
    assert np.array_equal(vertices, [[0, 0], [2, 0], [2, 2], [0, 2]])


# --- mass properties ----------------------------------------------------------------------

def test_pymunk_moment_is_about_the_origin():
    triangle = np.array([[10.0, 10.0], [12.0, 10.0], [12.0, 11.0]])
    mass, centroid, inertia = polygon_mass_properties(triangle, 1.0)
    about_origin = pymunk.moment_for_poly(mass, triangle.tolist())
    assert close(about_origin, inertia + mass * centroid @ centroid)
    assert close(pymunk.moment_for_poly(mass, (triangle - centroid).tolist()), inertia)


def test_mass_properties_match_pymunk_on_random_convex_polygons():
    rng = np.random.default_rng(7)
    for vertices in random_convex(rng, 200):
        density = rng.uniform(0.1, 10.0)
        mass, centroid, inertia = polygon_mass_properties(vertices, density)
        area = pymunk.area_for_poly(vertices.tolist())
        assert close(mass, density * area)
        cog = pymunk.Poly(None, vertices.tolist()).center_of_gravity
        assert np.allclose(centroid, cog, rtol=0, atol=REL * np.abs(vertices).max())
        assert close(inertia, pymunk.moment_for_poly(mass, (vertices - centroid).tolist()))


def side_lengths_squared(triangle):
    return np.sum((triangle - np.roll(triangle, 1, axis=0)) ** 2)


def test_mass_properties_match_closed_forms():
    rng = np.random.default_rng(8)
    for _ in range(50):
        w, h, density = rng.uniform(0.01, 100.0, 3)
        mass, centroid, inertia = polygon_mass_properties(box(w, h) + rng.uniform(-50, 50, 2), density)
        assert close(mass, density * w * h) and close(inertia, mass * (w * w + h * h) / 12)
    for k in range(3, 40):
        r = rng.uniform(0.1, 10.0)
        mass, centroid, inertia = polygon_mass_properties(regular(k, r), 1.0)
        assert close(mass, 0.5 * k * r * r * np.sin(2 * np.pi / k))
        # fan of k isosceles triangles about the centre: each m_t·r²·(2 + cos(2π/k)) / 6
        assert close(inertia, mass * r * r * (2 + np.cos(2 * np.pi / k)) / 6)
        assert np.all(np.abs(centroid) <= 1e-14 * r)
    for triangle in random_convex(rng, 50):
        triangle = triangle[:3]
        mass, centroid, inertia = polygon_mass_properties(triangle, 2.0)
        (ux, uy), (vx, vy) = triangle[1] - triangle[0], triangle[2] - triangle[0]
        assert close(mass, 2.0 * abs(ux * vy - uy * vx) / 2)
        assert np.allclose(centroid, triangle.mean(axis=0), rtol=0, atol=1e-14 * np.abs(triangle).max())
        assert close(inertia, mass * side_lengths_squared(triangle) / 36)


def test_mass_properties_far_from_the_origin_lose_no_digits():
    rng = np.random.default_rng(9)
    for vertices in random_convex(rng, 100, grid=2.0 ** -20):   # shifting by 1e6 is then exact
        shift = np.array([1e6, -1e6])
        near = polygon_mass_properties(vertices, 3.0)
        mass, centroid, inertia = polygon_mass_properties(vertices + shift, 3.0)
        assert close(mass, near[0]) and close(inertia, near[2])
        assert close(inertia, pymunk.moment_for_poly(mass, (vertices - near[1]).tolist()))
        assert np.allclose(centroid, near[1] + shift, rtol=0, atol=1e-15 * 1e6)


def test_circle_inertia():
    assert circle_inertia(2.0, 3.0) == 9.0
    assert np.array_equal(circle_inertia(np.array([1.0, 2.0]), np.array([2.0, 1.0])), [2.0, 1.0])


# --- placement and bounding shapes ----------------------------------------------------------

def test_world_vertices_bounds_and_normals():
    body = box(2.0, 1.0)
    placed = world_vertices(body, 5.0, -1.0, np.pi / 2, np.empty((4, 2)))
    assert np.allclose(placed, [[5.5, -2.0], [5.5, 0.0], [4.5, 0.0], [4.5, -2.0]])
    assert np.allclose(polygon_bounds(placed), (4.5, -2.0, 5.5, 0.0))
    normals = edge_normals(placed, np.empty((4, 2)))
    assert np.allclose(normals, [[1, 0], [0, 1], [-1, 0], [0, -1]])
    rng = np.random.default_rng(10)
    for vertices in random_convex(rng, 50):
        normals = edge_normals(vertices, np.empty_like(vertices))
        edges = np.roll(vertices, -1, axis=0) - vertices
        assert np.allclose(np.hypot(*normals.T), 1.0) and np.allclose(np.sum(normals * edges, axis=1), 0.0)
        centre = vertices.mean(axis=0)                 # inside: every normal faces away from it
        assert np.all(np.sum(normals * (vertices - centre), axis=1) > 0)


def test_bounding_radius_holds_every_vertex():
    rng = np.random.default_rng(11)
    for vertices in random_convex(rng, 50):
        body = vertices - polygon_mass_properties(vertices)[1]
        assert bounding_radius(body) == pytest.approx(np.hypot(*body.T).max(), rel=1e-15)


def box_area_at(vertices, angles):
    """Area of the rectangle around vertices (k, 2) with sides along each angle: (m,)."""
    u = np.stack([np.cos(angles), np.sin(angles)], axis=1)
    along = vertices @ u.T
    across = vertices @ np.stack([-u[:, 1], u[:, 0]], axis=1).T
    return np.ptp(along, axis=0) * np.ptp(across, axis=0)


def test_oriented_box_is_the_smallest_rectangle_and_holds_the_polygon():
    rng = np.random.default_rng(12)
    shapes = random_convex(rng, 150) + [box(3.0, 1.0), regular(6, 1.0), regular(40, 2.0)]
    for vertices in shapes:
        cx, cy, half_w, half_h, angle = oriented_box(vertices)
        area = 4 * half_w * half_h
        scale = np.ptp(vertices, axis=0).max()
        assert area <= np.prod(np.ptp(vertices, axis=0)) * (1 + 1e-12)
        u = np.array([np.cos(angle), np.sin(angle)])
        local = vertices - (cx, cy)
        assert np.all(np.abs(local @ u) <= half_w + 1e-12 * scale)
        assert np.all(np.abs(local @ (-u[1], u[0])) <= half_h + 1e-12 * scale)
        edges = np.roll(vertices, -1, axis=0) - vertices
        by_edges = box_area_at(vertices, np.arctan2(edges[:, 1], edges[:, 0])).min()
        assert area == pytest.approx(by_edges, rel=1e-9)
        assert area <= box_area_at(vertices, np.linspace(0, np.pi, 2001)).min() * (1 + 1e-9)
