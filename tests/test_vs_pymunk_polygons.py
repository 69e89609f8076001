"""Polygon bodies against pymunk (collisim.analysis.reference): the mirror and plain pymunk build
the same bodies as the World, and collisim's discrete engine and the mirror agree with closed
forms for a box bouncing, a box sliding under friction and a stack of boxes standing.

Tolerances come from the step: pymunk's semi-implicit Euler moves each body with the velocity
of the end of its step, so it slides v·dt further before friction stops it, and its bounce
(restitution applied to the pre-gravity velocity) may gain up to a step's worth of speed.
"""
import numpy as np
import pymunk
import pytest

import collisim
from collisim.analysis.compare import compare, format_table
from collisim.analysis.reference import simulate_pymunk
from collisim.analysis.reference.plain_pymunk import PlainPymunk
from collisim.analysis.reference.pymunk_mirror import Mirror
from collisim.shapes import box, regular

pytestmark = pytest.mark.comparison

FPS, G = 60.0, 9.81
BOX = (0.0, 0.0, 10.0, 10.0)
W, H = 1.0, 0.5           # the test box's width and height


def both(world, seconds):
    """(collisim discrete, pymunk mirror) trajectories of `world`."""
    scene = collisim.Scene(world=world, fps=FPS, seconds=seconds, method="discrete")
    return collisim.simulate(scene), simulate_pymunk(scene)


def test_builders_give_the_worlds_bodies():
    world = collisim.World([[2.0, 2.0], [5.0, 2.0], [8.0, 2.0]], masses=[1.0, 2.0, 3.0], radii=0.4,
                           polygons=[box(W, H), regular(3, 0.6), None], angles=[0.3, 1.0, 0.5],
                           angular_velocities=[1.0, -2.0, 0.0], box=BOX, friction=0.36, restitution=0.25)
    pyramid = np.array([[0.0, 0.0], [1.0, 0.0], [0.5, 2.0]])   # a centroid away from the origin
    uneven = collisim.World([[5.0, 5.0]], polygons=[pyramid], box=BOX)
    for w in (world, uneven):
        for space, bodies in ((Mirror(w).space, Mirror(w).bodies), (PlainPymunk(w).space, PlainPymunk(w).bodies)):
            for i, body in enumerate(bodies):
                assert body.mass == w.masses[i] and body.position == pytest.approx(w.positions[i], abs=1e-15)
                assert body.angle == w.angles[i] and body.angular_velocity == w.angular_velocities[i]
                if w.shapes[i] == collisim.core.kinds.POLYGON:
                    (shape,) = body.shapes
                    local = w.body_vertices[w.vertex_start[i]:w.vertex_start[i + 1]]
                    # the same vertices (Chipmunk's hull may start at another one)
                    theirs = np.array(shape.get_vertices())
                    apart = np.linalg.norm(theirs[:, None] - local[None], axis=2)
                    assert len(theirs) == len(local) and apart.min(axis=1).max() < 1e-14
                    assert body.moment == pytest.approx(w.inertias[i], rel=1e-12)
                    # and pymunk's own moment for these vertices is the World's: an independent check
                    assert pymunk.moment_for_poly(w.masses[i], local.tolist()) == pytest.approx(w.inertias[i], rel=1e-9)
                    assert body.center_of_gravity == (0.0, 0.0)
                    assert shape.center_of_gravity == pytest.approx((0.0, 0.0), abs=1e-12)
    # the products are the World's e and μ on every contact (Chipmunk multiplies them), in the
    # mirror and in plain pymunk alike
    for shapes in (list(Mirror(world).space.shapes), list(PlainPymunk(world).space.shapes)):
        for other in shapes:
            assert shapes[0].friction * other.friction == pytest.approx(0.36, rel=1e-12)
            assert shapes[0].elasticity * other.elasticity == pytest.approx(0.25, rel=1e-12)
    # a circle with friction turns: it gets the World's moment, not the frictionless mirror's infinity
    assert Mirror(world).bodies[2].moment == pytest.approx(world.inertias[2], rel=1e-12)


def test_a_spinning_hexagon_records_its_angle_in_both():
    world = collisim.World([[5.0, 5.0]], [[1.0, 0.5]], polygons=[regular(6, 0.5)], angles=0.2,
                           angular_velocities=3.0, box=BOX)
    for traj in both(world, 1.0):
        assert traj.angles[:, 0] == pytest.approx(0.2 + 3.0 * traj.times, abs=1e-12)
        assert traj.angular_velocities[-1, 0] == pytest.approx(3.0, abs=1e-12)


def test_a_box_dropped_flat_bounces_back_to_its_height():
    # e = 1, no friction: the box falls 2.75 onto its long side and must rise back to y = 3.
    # pymunk's bounce is ~1 % high at 60 fps (measured 3.026); collisim's is exact to round-off.
    drop = 3.0
    world = collisim.World([[5.0, drop]], polygons=[box(W, H)], box=BOX, gravity=(0.0, -G), restitution=1.0)
    collisim_run, pymunk_run = both(world, 1.6)
    for traj, tolerance in ((collisim_run, 1e-6), (pymunk_run, 0.02)):
        y = traj.positions[:, 0, 1]
        low = int(np.argmin(y))
        assert 0 < low < len(y) - 10                     # it bounced and flew again
        assert y[low:].max() == pytest.approx(drop, abs=tolerance * (drop - H / 2))
        assert np.abs(traj.angles).max() < 1e-9          # a flat landing does not tip it
        assert np.ptp(traj.positions[:, 0, 0]) < 1e-12


def test_a_box_sliding_on_the_floor_decelerates_at_mu_g():
    mu, v0 = 0.5, 4.0
    world = collisim.World([[2.0, H / 2]], [[v0, 0.0]], polygons=[box(W, H)], box=BOX, gravity=(0.0, -G),
                           restitution=0.0, friction=mu)
    stop_time, stop_distance = v0 / (mu * G), v0 ** 2 / (2 * mu * G)
    for traj in both(world, 1.2):
        v, t = traj.velocities[:, 0, 0], traj.times
        sliding = t < stop_time - 1.0 / FPS
        # v = v0 − μ·g·t while it slides (both integrate velocities exactly under constant force)
        assert v[sliding] == pytest.approx(v0 - mu * G * t[sliding], abs=1e-9)
        assert abs(v[-1]) < 1e-9
        # pymunk moves with the velocity of the end of each step: up to v0·dt further
        assert traj.positions[-1, 0, 0] - 2.0 == pytest.approx(stop_distance, abs=v0 / FPS * 1.05)
        assert np.abs(traj.angles).max() < 0.01           # friction at the floor does not tip it


def test_a_stack_of_three_boxes_stands():
    world = collisim.World([[5.0, H / 2], [5.0, 1.5 * H], [5.0, 2.5 * H]], polygons=[box(W, H)] * 3, box=BOX,
                           gravity=(0.0, -G), restitution=0.0, friction=0.5)
    for traj in both(world, 5.0):
        assert np.abs(traj.positions - traj.positions[0]).max() < 0.02 * H   # measured < 0.006 H in both
        assert np.abs(traj.angles).max() < 0.01
        assert np.abs(traj.velocities[-1]).max() < 1e-6


def test_compare_runs_a_polygon_world_and_reports_that_ccd_cannot():
    world = collisim.World([[3.0, 2.0], [6.0, 2.0]], [[1.0, 0.0], [-1.0, 0.0]], polygons=[box(W, H), None],
                           radii=0.4, box=BOX, gravity=(0.0, -G), restitution=0.5, friction=0.3)
    scene = collisim.Scene(world=world, fps=FPS, seconds=0.5, method="discrete")
    rows = compare(scene, methods=["discrete x1", "ccd", "pymunk x1"])
    by_method = {row["method"]: row for row in rows}
    assert by_method["ccd"]["error"] and by_method["ccd"]["cost"] is None
    for method in ("discrete x1", "pymunk x1"):
        assert by_method[method]["error"] is None and by_method[method]["energy_drift"] is not None
    assert "ccd: could not run (method ccd covers circles, segments and maps; this scene has polygons" in format_table(rows)
    for method in ("discrete x1", "pymunk x1"):   # the narrow phase's depth, in radii: contacts stay shallow
        assert 0.0 <= by_method[method]["max_overlap"] < 0.1
    assert by_method["discrete x1"]["missed_pairs"] is None   # a circle measure: n/a with polygons


def test_the_polygons_benchmark_runs_on_a_tiny_setting():
    # a smoke test, not timed: a few steps of the shipped scene through every engine and the table
    from collisim.analysis.bench.polygons import asleep_cost, format_asleep, format_rows, load_world, run
    world, fps = load_world()
    rows, extra = run(seconds=0.1, repeats=1, world=world, fps=fps)
    assert [row["phase"].split(" (")[0] for row in rows] == ["falling", "whole scene"]
    assert {"collisim", "pymunk", "pymunk sleeping"} <= set(rows[0]["ms"])
    assert all(ratio > 0 for row in rows for ratios in row["ratios"].values() for ratio in ratios)
    assert "collisim / each" in format_rows(rows, extra)
    asleep = asleep_cost(world, fps, repeats=1)   # every engine's bodies asleep before it is timed
    assert all(k == world.n for k, _ in asleep["asleep"].values()) and "fully asleep" in format_asleep(asleep)
    assert all(us > 0 for times in asleep["us"].values() for us in times)
    with pytest.raises(ValueError, match="repeats"):
        run(seconds=0.1, repeats=0, world=world, fps=fps)
