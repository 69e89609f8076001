"""Circles resting on segments and on a collision map under gravity, in the discrete method: a
segment or the map holds a stack or a pile in the contact solver as the box floor does
(response/rows.circle_segment_manifolds, circle_map_manifold). Left to the bounce alone, a
stack of ten on a segment floor collapsed into one place (18 radii off its heights), and two
circles of a pile in a V of segments or of a map came to coincide."""
import warnings

import numpy as np
import pytest

import collisim

R = 0.5
BOX = (0.0, 0.0, 20.0, 32.0)
CELL = 0.1


def map_of(free) -> collisim.CollisionMap:
    """The collision map of BOX whose free space is where free(x, y) holds, at CELL."""
    height, width = int(BOX[3] / CELL), int(BOX[2] / CELL)
    rows, cols = np.mgrid[0:height, 0:width]
    x, y = (cols + 0.5) * CELL, (height - rows - 0.5) * CELL
    return collisim.CollisionMap.from_image(np.where(free(x, y), 255, 0).astype(np.uint8), cell=CELL)


FLOORS = {   # what holds the stack at y = 1, as keyword arguments of World
    "box": dict(box=(0.0, 1.0, 20.0, 32.0)),
    "segment": dict(box=BOX, segments=[[0.0, 1.0, 20.0, 1.0]]),
    "map": dict(box=BOX, map=map_of(lambda x, y: y > 1.0)),
}
V_SEGMENTS = [[0.0, 6.0, 10.0, 0.5], [20.0, 6.0, 10.0, 0.5]]
V_STATICS = {
    "segments": dict(segments=V_SEGMENTS),
    "map": dict(map=map_of(lambda x, y: y > 0.5 + 0.55 * np.abs(x - 10.0))),
}


def settled(world, fps=30, seconds=4.0):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return collisim.simulate(collisim.Scene(world=world, fps=fps, seconds=seconds, method="discrete"))


def stack(floor: str, n: int = 10):
    """n circles in a column, each 1 % of a radius above the one below, dropped (e = 0) on a
    floor at y = 1."""
    positions = np.column_stack([np.full(n, 10.0), 1.0 + R + 2 * R * np.arange(n) + 0.01 * R * np.arange(n)])
    return collisim.World(positions=positions, radii=R, gravity=(0, -9.8), restitution=0.0, **FLOORS[floor])


@pytest.mark.parametrize("floor", ["segment", "map"])
def test_a_stack_on_a_static_floor_stands_where_it_stands_on_the_box_floor(floor):
    heights = 1.0 + R + 2 * R * np.arange(10)
    on_box, on_static = settled(stack("box")), settled(stack(floor))
    assert np.abs(on_static.positions[-1][:, 1] - heights).max() < 0.05 * R
    assert np.abs(on_static.positions[-1][:, 0] - 10.0).max() < 1e-9
    if floor == "segment":   # the same rows as the box floor's: the same numbers
        assert np.abs(on_static.positions[-1] - on_box.positions[-1]).max() < 1e-9 * R
    assert np.abs(on_static.velocities[-1]).max() < 1e-3


def pair_overlap(positions) -> float:
    """The largest overlap of two circles of radius R, in radii."""
    gaps = np.linalg.norm(positions[:, None] - positions[None], axis=-1) + np.eye(len(positions)) * 1e9
    return (2 * R - gaps.min()) / R


def line_distance(positions, segment) -> np.ndarray:
    """Signed distance of each centre to the segment's line, positive above it."""
    x0, y0, x1, y1 = segment
    normal = np.array([-(y1 - y0), x1 - x0]) / np.hypot(x1 - x0, y1 - y0)
    normal = normal if normal[1] > 0 else -normal
    return (positions - [x0, y0]) @ normal


@pytest.mark.parametrize("statics", sorted(V_STATICS))
@pytest.mark.parametrize("fps", [30, 60])
def test_a_pile_in_a_v_keeps_its_circles_apart_and_above_it(fps, statics):
    n = 80
    rng = np.random.default_rng(2)
    xs, ys = np.meshgrid(np.arange(3.0, 17.0, 1.2), np.arange(8.0, 30.0, 1.2))
    positions = np.column_stack([xs.ravel(), ys.ravel()])[:n] + rng.uniform(-0.05, 0.05, (n, 2))
    world = collisim.World(positions=positions, radii=R, box=BOX, gravity=(0, -9.8), restitution=0.0,
                           **V_STATICS[statics])
    run = settled(world, fps=fps, seconds=6.0)
    last_second = run.positions[-fps:]
    assert max(pair_overlap(p) for p in last_second[::5]) < 0.05     # was 1.99 and 1.97 radii at 30 fps
    for segment in V_SEGMENTS:                                          # the map's V has the same outline
        assert (line_distance(last_second.reshape(-1, 2), segment) > R - 0.05 * R - (CELL if statics == "map" else 0)).all()
    assert np.abs(run.velocities[-1]).max() < 0.2                       # and the pile has come (nearly) to rest


@pytest.mark.parametrize("friction", [0.0, 0.5])
def test_a_ball_on_a_sloped_segment_slides_or_rolls_as_the_closed_form_says(friction):
    """On a 20° segment a frictionless ball slides, s = ½·g·sinθ·t²; with friction 0.5 (more than
    the tan θ / 3 rolling needs) a uniform disc rolls, s = ⅓·g·sinθ·t² and ω = -⅔·g·sinθ·t / r.
    The segment holds it in the contact solver, where friction acts, all the way down: its speed
    soon passes the rest speed, so only its touching the segment keeps its rows (a lone circle
    that fast was left to the bounce, without friction, and slid 36 % too far)."""
    slope, g, t = np.radians(20.0), 9.8, 1.0
    normal = np.array([np.sin(slope), np.cos(slope)])
    start = np.array([2.0, 10.0 - 2.0 * np.tan(slope)]) + R * normal
    world = collisim.World(positions=[start], radii=R, box=(0, -5, 20, 15), gravity=(0, -g), restitution=0.0,
                           friction=friction, segments=[[0.0, 10.0, 20.0, 10.0 - 20.0 * np.tan(slope)]])
    run = settled(world, fps=60, seconds=t)
    share = 1.0 if friction == 0.0 else 2.0 / 3.0           # of g·sinθ: sliding, or rolling (I = ½·m·r²)
    travelled = np.linalg.norm(run.positions[-1][0] - start)
    assert travelled == pytest.approx(0.5 * share * g * np.sin(slope) * t ** 2, rel=0.01)
    spin = 0.0 if friction == 0.0 else -share * g * np.sin(slope) * t / R
    assert run.angular_velocities[-1][0] == pytest.approx(spin, rel=0.01, abs=1e-9)
    assert abs(line_distance(run.positions[:, 0], world.segments[0]) - R).max() < 0.01 * R   # on it throughout
