"""Outcomes against a second outside reference, Box2D 2.3 (collisim.analysis.reference.box2d_world):
a box sliding to rest under friction, boxes and discs bouncing with restitution, a disc rolling,
a stack and a pyramid standing. Each case also has its closed form, so a disagreement says which
engine is wrong.

Tolerances allow for Box2D's own: bodies rest 0.01 apart (b2_polygonRadius), overlaps of 0.005
are left alone (b2_linearSlop), and both engines integrate semi-implicitly, a step's worth of
travel v·dt apart at most.
"""
import numpy as np
import pytest

import collisim
from collisim.shapes import box

Box2D = pytest.importorskip("Box2D")
from collisim.analysis.reference.box2d_world import Box2DWorld  # noqa: E402  (needs Box2D)

pytestmark = pytest.mark.comparison

FPS, G = 60.0, 9.81
BOX = (0.0, 0.0, 20.0, 20.0)


def both(world, seconds, fps=FPS):
    """(collisim's discrete trajectory, Box2D's world after the same frames)."""
    run = collisim.simulate(collisim.Scene(world=world, fps=fps, seconds=seconds, method="discrete"))
    reference = Box2DWorld(world, fps)
    reference.step(round(seconds * fps))
    return run, reference


def test_a_box_slides_to_rest_where_friction_stops_it():
    """v₀ = 4 at μ = 0.4 stops after v₀²/(2μg) = 2.04, without turning."""
    v0, mu = 4.0, 0.4
    world = collisim.World([[3.0, 0.25]], velocities=[[v0, 0.0]], polygons=[box(1.0, 0.5)], box=BOX,
                           gravity=(0.0, -G), friction=mu, restitution=0.0)
    run, reference = both(world, 2.0)
    expected = v0 ** 2 / (2 * mu * G)
    ours, theirs = run.positions[-1][0, 0] - 3.0, reference.positions[0, 0] - 3.0
    assert ours == pytest.approx(expected, abs=v0 / FPS)
    assert theirs == pytest.approx(expected, abs=v0 / FPS)
    assert abs(run.angles[-1][0]) < 1e-6 and abs(reference.angles[0]) < 1e-6
    assert np.abs(run.velocities[-1][0]).max() < 1e-6 and np.abs(reference.velocities[0]).max() < 1e-6


@pytest.mark.parametrize("shape", ["box", "disc"])
def test_a_drop_rebounds_to_e_squared_of_its_height(shape):
    """Dropped from 3 above the floor at e = 0.6, a body climbs back to e²·3 = 1.08 (both engines
    apply e to the velocity of approach; the first apex is read from the frames)."""
    e, h = 0.6, 3.0
    polygons = [box(1.0, 1.0)] if shape == "box" else None
    world = collisim.World([[5.0, 0.5 + h]], radii=0.5, polygons=polygons, box=BOX, gravity=(0.0, -G),
                           restitution=e)
    fall = np.sqrt(2 * h / G)
    run = collisim.simulate(collisim.Scene(world=world, fps=FPS, seconds=round(2.2 * fall * FPS) / FPS, method="discrete"))
    reference = Box2DWorld(world, FPS)
    heights = []
    for _ in range(len(run.positions) - 1):
        reference.step()
        heights.append(reference.positions[0, 1])
    after = slice(int(1.2 * fall * FPS), None)              # past the bounce
    ours, theirs = run.positions[after, 0, 1].max() - 0.5, max(heights[after]) - 0.5
    step = np.sqrt(2 * G * h) / FPS                          # a frame's travel at impact
    assert ours == pytest.approx(e * e * h, abs=step)
    assert theirs == pytest.approx(e * e * h, abs=step + 0.01)
    assert ours == pytest.approx(theirs, abs=step + 0.01)


def test_a_head_on_pair_leaves_with_newtons_velocities():
    """Discs of masses 1 and 3 meet head on at ±2 with e = 0.5: v₁' = v₁ - (1+e)·m₂/(m₁+m₂)·(v₁-v₂)."""
    e, m1, m2, v1, v2 = 0.5, 1.0, 3.0, 2.0, -2.0
    world = collisim.World([[8.0, 10.0], [12.0, 10.0]], velocities=[[v1, 0.0], [v2, 0.0]], radii=0.5,
                           masses=[m1, m2], box=BOX, restitution=e)
    run, reference = both(world, 1.5)
    j = (1 + e) * (v1 - v2) / (1 / m1 + 1 / m2)
    expected = np.array([v1 - j / m1, v2 + j / m2])
    np.testing.assert_allclose(run.velocities[-1][:, 0], expected, atol=1e-9)
    np.testing.assert_allclose(reference.velocities[:, 0], expected, atol=1e-4)


def test_a_disc_rolls_down_the_box_floor_tilted():
    """Gravity tilted 20° on a disc at μ = 0.5: it rolls, a = ⅔·g·sinθ and ω·r = -v."""
    theta, t = np.radians(20.0), 1.0
    gravity = (G * np.sin(theta), -G * np.cos(theta))
    world = collisim.World([[2.0, 0.5]], radii=0.5, box=BOX, gravity=gravity, friction=0.5, restitution=0.0)
    run, reference = both(world, t)
    expected = (2.0 / 3.0) * G * np.sin(theta) * t
    assert run.velocities[-1][0, 0] == pytest.approx(expected, rel=0.01)
    assert reference.velocities[0, 0] == pytest.approx(expected, rel=0.01)
    assert run.angular_velocities[-1][0] * 0.5 == pytest.approx(-expected, rel=0.01)
    assert reference.angular_velocities[0] * 0.5 == pytest.approx(-expected, rel=0.01)


def stacked(n: int, size: float = 1.0):
    """A column of n unit boxes on the floor, each resting on the one below."""
    return [[10.0, size * (k + 0.5)] for k in range(n)]


def pyramid(base: int, size: float = 1.0):
    """Box2D's pyramid: rows of base, base-1, ... boxes, each row centred on the one below."""
    return [[10.0 + size * (column - 0.5 * (base - row - 1)), size * (row + 0.5)]
            for row in range(base) for column in range(base - row)]


@pytest.mark.parametrize("layout", [stacked(8), pyramid(6)], ids=["stack of 8", "pyramid of base 6"])
def test_stacks_stand_in_both(layout):
    """At μ = 0.6, e = 0 a stack and a pyramid stand for 5 s: no box moves more than 0.05 (Box2D
    settles its boxes b2_polygonRadius apart: 0.01 a row) and none turns."""
    world = collisim.World(layout, polygons=[box(1.0, 1.0)] * len(layout), box=BOX, gravity=(0.0, -G),
                           friction=0.6, restitution=0.0)
    run, reference = both(world, 5.0)
    start = np.asarray(layout)
    ours = np.linalg.norm(run.positions[-1] - start, axis=1).max()
    theirs = np.linalg.norm(reference.positions - start, axis=1).max()
    rows = max(p[1] for p in layout) + 0.5
    assert ours < 0.05 and theirs < 0.05 + 0.01 * rows
    assert np.abs(run.angles[-1]).max() < 0.01 and np.abs(reference.angles).max() < 0.01
