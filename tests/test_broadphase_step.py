"""The grid as the discrete step calls it (broadphase/step.py's candidate_pairs on a GridState:
home cells and boxes gathered into cell order, grid_home.py, or grid.py's filing when the boxes
are too wide) against the plain numpy all-pairs reference of test_broadphase.py: exactly the
overlapping pairs, each once, step after step."""

import numpy as np
import pytest
from hypothesis import given, settings
from numba import njit
from strategies import box_arrays
from test_broadphase import DEGENERATE, circles, gas, reference_pairs

from collisim.broadphase.step import box_grid, candidate_pairs


@njit
def _step_pairs(state, lo, hi):
    return candidate_pairs(state, lo, hi)


def step_grid(lo, hi, n=None):
    """The grid state the discrete step would keep for these boxes (radii: their half widths;
    the world's box: around them), with scratch for n boxes."""
    radii = 0.5 * np.max(hi - lo, axis=1) if len(lo) else np.ones(1)
    corner_lo, corner_hi = (lo.min(axis=0), hi.max(axis=0)) if len(lo) else (np.zeros(2), np.ones(2))
    box = np.r_[corner_lo, np.maximum(corner_hi, corner_lo + 1e-9)]
    return box_grid(box, np.resize(radii, len(lo) if n is None else n))


def assert_step_grid_matches_reference(lo, hi, state=None, calls=2):
    """The step's grid (home cells and gathered boxes, or grid.py's filing when boxes are too
    wide) finds exactly the overlapping pairs, each once, i < j, call after call."""
    lo, hi = np.ascontiguousarray(lo, float), np.ascontiguousarray(hi, float)
    state = step_grid(lo, hi) if state is None else state
    for _ in range(calls):
        pairs = _step_pairs(state, lo, hi)
        assert pairs.dtype == np.intp and pairs.shape[1:] == (2,)
        assert np.all(pairs[:, 0] < pairs[:, 1])
        keys = np.sort(pairs[:, 0] * len(lo) + pairs[:, 1])
        assert np.all(np.diff(keys) > 0), "each pair once"
        np.testing.assert_array_equal(np.stack((keys // len(lo), keys % len(lo)), axis=1), reference_pairs(lo, hi))
        assert not state.count.any(), "the cell counts are left zero for the next step"
    return state


@settings(max_examples=60, deadline=None)
@given(boxes=box_arrays().filter(lambda boxes: len(boxes[0]) >= 2))
def test_step_grid_random_boxes_match_brute_force(boxes):
    assert_step_grid_matches_reference(*boxes)


@pytest.mark.parametrize("case", DEGENERATE)
def test_step_grid_degenerate_inputs(case):
    assert_step_grid_matches_reference(*DEGENERATE[case])


STEP_CASES = {
    "a gas": gas(2000, 150, seed=12),
    "a gas on whole numbers (ties)": tuple(np.round(a) for a in gas(2000, 150, seed=13)),
    "all in one cell": circles(np.random.default_rng(14).uniform(0, 0.1, (300, 2)), 1.0),
    "duplicates": circles(np.repeat(np.random.default_rng(15).uniform(0, 40, (100, 2)), 3, axis=0), 1.0),
    "boxes a little wider than the cells": circles(np.random.default_rng(16).uniform(0, 100, (500, 2)),
                                                   np.r_[2.5, np.ones(499)]),
    "boxes much wider than the cells": circles(np.random.default_rng(17).uniform(0, 100, (500, 2)),
                                               np.r_[30.0, np.ones(499)]),
    "zero-size boxes": (np.full((30, 2), 2.0), np.full((30, 2), 2.0)),
    # every box touches its eight neighbours edge to edge or corner to corner, which a box that
    # reaches the next column or row by its very edge alone must still find
    "a lattice of boxes edge to edge": tuple(np.stack(np.meshgrid(np.arange(30.0), np.arange(20.0)), -1).reshape(-1, 2)
                                             + offset for offset in (0.0, 1.0)),
    "two boxes": circles([[0, 0], [1, 0]], 1.0),
}


@pytest.mark.parametrize("case", STEP_CASES)
def test_step_grid_cases(case):
    assert_step_grid_matches_reference(*STEP_CASES[case])


def test_step_grid_keeps_up_as_boxes_move_and_fewer_than_its_scratch():
    lo, hi = gas(1500, 120, seed=18)
    state = step_grid(lo, hi, n=2000)
    for shift in np.random.default_rng(19).normal(0, 0.3, (5, 1500, 2)):
        lo, hi = lo + shift, hi + shift
        assert_step_grid_matches_reference(lo, hi, state, calls=1)
    assert_step_grid_matches_reference(lo[:700], hi[:700], state, calls=1)


def test_step_grid_with_too_little_scratch_files_boxes_in_every_cell():
    lo, hi = gas(300, 60, seed=20)
    assert_step_grid_matches_reference(lo, hi, step_grid(lo[:100], hi[:100]))


@pytest.mark.parametrize("n", [0, 1])
def test_step_grid_runs_a_world_of_fewer_than_two_bodies(n):
    import collisim
    world = collisim.World(positions=np.full((n, 2), 5.0), velocities=np.ones((n, 2)))
    trajectory = collisim.simulate(collisim.Scene(world=world, seconds=0.1, broadphase="grid"))
    assert trajectory.frames == 6 and not trajectory.candidates.any()


@pytest.mark.parametrize("axis", [0, 1])
def test_step_grid_finds_a_box_that_reaches_the_next_cell_by_its_edge_alone(axis):
    """Box A's far edge lies exactly on the boundary of the next column (row), where box B starts:
    touching counts, so the scan must look past A's own cell for it."""
    from collisim.broadphase.grid_home import home_cells_per_unit

    def boxes(x):   # A, B along the axis; two unit boxes far off set the cells' width and the grid
        lo = np.array([[x - 0.75, 0.25], [x, 0.25], [0.0, 10.0], [3.0, 10.0]])
        hi = np.array([[x, 0.75], [x + 0.75, 0.75], [1.0, 11.0], [4.0, 11.0]])
        return (lo, hi) if axis == 0 else (lo[:, ::-1].copy(), hi[:, ::-1].copy())

    state = step_grid(*boxes(1.0))
    per_unit = home_cells_per_unit(*boxes(1.0), state.finest, state.cells_per_unit)
    x = 1.0 / per_unit
    while x * per_unit != 1.0:   # the float whose cell coordinate is exactly the next column's
        x = np.nextafter(x, 2.0 if x * per_unit < 1.0 else 0.0)
    lo, hi = boxes(x)
    assert_step_grid_matches_reference(lo, hi, step_grid(lo, hi))
    assert len(reference_pairs(lo, hi)) == 1
