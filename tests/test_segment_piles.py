"""Circles resting on segments under gravity, in the discrete method: a segment holds a stack or
a pile in the contact solver as the box floor does (response/rows.circle_segment_manifolds).
Left to the segment bounce alone, a stack of ten on a segment floor collapsed into one place
(18 radii off its heights) and two circles of a pile in a V of segments came to coincide."""
import warnings

import numpy as np
import pytest

import collisim

R = 0.5


def stack(floor: str, n: int = 10):
    """n circles in a column, each 1 % of a radius above the one below, dropped (e = 0) on the
    box floor at y = 1 or on a segment across the box at y = 1."""
    positions = np.column_stack([np.full(n, 5.0), 1.0 + R + 2 * R * np.arange(n) + 0.01 * R * np.arange(n)])
    on_segment = floor == "segment"
    return collisim.World(positions=positions, radii=R, gravity=(0, -9.8), restitution=0.0,
                          box=(0, 0, 10, 30) if on_segment else (0, 1, 10, 30),
                          segments=[[0.0, 1.0, 10.0, 1.0]] if on_segment else None)


def settled(world, fps=30, seconds=4.0, substeps=1):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return collisim.simulate(collisim.Scene(world=world, fps=fps, seconds=seconds, method="discrete",
                                                substeps=substeps))


def test_a_stack_on_a_segment_stands_where_it_stands_on_the_box_floor():
    heights = 1.0 + R + 2 * R * np.arange(10)
    on_floor, on_segment = settled(stack("box")), settled(stack("segment"))
    assert np.abs(on_segment.positions[-1][:, 1] - heights).max() < 0.05 * R
    assert np.abs(on_segment.positions[-1][:, 0] - 5.0).max() < 1e-9
    assert np.abs(on_segment.positions[-1] - on_floor.positions[-1]).max() < 1e-9 * R
    assert np.abs(on_segment.velocities[-1]).max() < 1e-3


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


V = [[0.0, 6.0, 10.0, 0.5], [20.0, 6.0, 10.0, 0.5]]


@pytest.mark.parametrize("fps", [30, 60])
def test_a_pile_in_a_v_of_segments_keeps_its_circles_apart_and_above_them(fps):
    n = 80
    rng = np.random.default_rng(2)
    xs, ys = np.meshgrid(np.arange(3.0, 17.0, 1.2), np.arange(8.0, 30.0, 1.2))
    positions = np.column_stack([xs.ravel(), ys.ravel()])[:n] + rng.uniform(-0.05, 0.05, (n, 2))
    world = collisim.World(positions=positions, radii=R, box=(0, 0, 20, 32), gravity=(0, -9.8), restitution=0.0,
                           segments=V)
    run = settled(world, fps=fps, seconds=6.0)
    last_second = run.positions[-fps:]
    assert max(pair_overlap(p) for p in last_second[::5]) < 0.05     # was 1.99 radii at 30 fps
    for segment in V:
        beside = np.abs(last_second[..., 0] - 10.0) <= 10.0             # every circle is over both arms
        assert (line_distance(last_second[beside], segment) > R * 0.95).all()
    speeds = np.linalg.norm(run.velocities[-1], axis=1)
    assert speeds.max() < 0.05                                          # and the pile has come to rest
