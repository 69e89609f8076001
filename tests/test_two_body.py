"""Two-body elastic response against the closed form from momentum and energy conservation, through
the contact solver's own rows and impact phase (response/rows.py, response/solver.py)."""
import numpy as np
import pytest

import collisim
from collisim.response.pair_rows import pair_manifolds
from collisim.response.rows import SLOP, margins, new_found, new_rows, rows_from
from collisim.response.solver import POSITION_RATE, collide, solve_positions, solve_velocities

DT = 1 / 60


def closed_form(x1, x2, v1, v2, m1, m2):
    """The video's 2D elastic collision: both new velocities from the pre-collision ones."""
    d = x1 - x2
    u1 = v1 - 2 * m2 / (m1 + m2) * np.dot(v1 - v2, d) / np.dot(d, d) * d
    u2 = v2 - 2 * m1 / (m1 + m2) * np.dot(v2 - v1, -d) / np.dot(d, d) * (-d)
    return u1, u2


def bodies_of(positions, velocities, masses, radii):
    from collisim.engine.step_state import Bodies
    return Bodies(np.zeros(2, np.int8), positions, velocities, np.zeros(2), np.zeros(2), np.zeros((2, 2)), radii,
                  masses, 0.5 * masses * radii ** 2, np.zeros(3, np.int64), np.zeros((0, 2)))


def rows_of(positions, velocities, masses, radii):
    bodies = bodies_of(positions, velocities, masses, radii)
    margin = np.empty(2)
    margins(velocities, np.zeros(2), np.zeros((2, 2)), radii, DT, margin)
    rows = new_rows(2)
    found = new_found(1)
    k = pair_manifolds(bodies, np.zeros((0, 2)), margin, DT, np.array([[0, 1]]), found, 0, np.zeros(2, np.bool_),
                       np.zeros(1, np.bool_), None, np.zeros(2, np.bool_), np.zeros(2, np.bool_))
    count = rows_from(found, k, bodies, rows)
    return rows, count, bodies


def respond(x1, x2, v1, v2, m1, m2, r1=1.0, r2=1.0, e=1.0):
    """The impact phase on one pair: (velocities, hits, impulse, positions)."""
    positions, velocities = np.array([x1, x2], float), np.array([v1, v2], float)
    masses, radii = np.array([m1, m2], float), np.array([r1, r2], float)
    rows, count, b = rows_of(positions, velocities, masses, radii)
    collide(rows, count, velocities, b.angular_velocities, b.accelerations, 1 / masses, 1 / b.inertias, e, 0.0, 0.0, DT, 10)
    return velocities, int((rows.hit[:count] > 0).sum()), rows.hit[0], positions


def correct(x1, x2, m1, m2):
    """The position phase on one resting, overlapping pair of unit circles: the positions after."""
    positions, velocities = np.array([x1, x2], float), np.zeros((2, 2))
    masses, radii = np.array([m1, m2], float), np.ones(2)
    rows, count, b = rows_of(positions, velocities, masses, radii)
    push, shift, turn, shift_turn = np.zeros((2, 2)), np.zeros((2, 2)), np.zeros(2), np.zeros(2)
    args = velocities, b.angular_velocities, b.accelerations, 1 / masses, 1 / b.inertias
    solve_velocities(rows, count, *args, 0.0, DT, 10, push, turn)
    solve_positions(rows, count, *args, DT, 10, push, turn, shift, shift_turn)
    assert not push.any() and not turn.any() and not shift_turn.any()   # no impulse, no turn
    return positions + (push + shift) * DT


@pytest.mark.parametrize("ratio", [1.0, 3.0, 1000.0])
@pytest.mark.parametrize("geometry", ["head-on", "oblique"])
def test_elastic_pair_matches_the_closed_form(ratio, geometry):
    m1, m2 = 1.0, ratio
    x1 = np.array([0.0, 0.0])
    x2 = np.array([2.0, 0.0]) if geometry == "head-on" else np.array([2.0 * np.cos(0.6), 2.0 * np.sin(0.6)])
    v1, v2 = np.array([3.0, 0.5]), np.array([-1.0, 0.25])
    velocities, hits, impulse, _ = respond(x1, x2, v1, v2, m1, m2)
    u1, u2 = closed_form(x1, x2, v1, v2, m1, m2)
    assert hits == 1
    np.testing.assert_allclose(velocities[0], u1, rtol=1e-12, atol=1e-12 * np.abs(u1).max())
    np.testing.assert_allclose(velocities[1], u2, rtol=1e-12, atol=1e-12 * np.abs(u2).max())
    p_before, p_after = m1 * v1 + m2 * v2, m1 * velocities[0] + m2 * velocities[1]
    np.testing.assert_allclose(p_after, p_before, rtol=1e-12, atol=1e-12 * np.abs(p_before).max())
    ke = lambda a, b: 0.5 * (m1 * a @ a + m2 * b @ b)  # noqa: E731
    assert ke(*velocities) == pytest.approx(ke(v1, v2), rel=1e-12)
    assert impulse == pytest.approx(np.linalg.norm(m1 * (velocities[0] - v1)), rel=1e-12)


def test_restitution_scales_the_normal_relative_speed():
    velocities, _, _, _ = respond([0, 0], [2, 0], [2.0, 1.0], [-1.0, 0.0], 1.0, 2.0, e=0.5)
    assert velocities[1, 0] - velocities[0, 0] == pytest.approx(0.5 * 3.0)
    assert velocities[0, 1] == 1.0   # tangential components untouched


def test_overlapping_but_separating_pair_is_left_alone():
    velocities, hits, impulse, _ = respond([0, 0], [1.5, 0], [-1.0, 0.0], [1.0, 0.0], 1.0, 1.0)
    assert hits == 0 and impulse == 0.0
    np.testing.assert_array_equal(velocities, [[-1.0, 0.0], [1.0, 0.0]])


def test_overlap_is_removed_along_the_normal_weighted_by_inverse_mass():
    positions = correct([0, 0], [1.0, 0], 1.0, 3.0)
    # overlap 1, of which a fifth beyond the slop goes in a step: the light particle moves 3/4
    moved = POSITION_RATE * (1.0 - SLOP)
    np.testing.assert_allclose(positions, [[-0.75 * moved, 0.0], [1.0 + 0.25 * moved, 0.0]], rtol=1e-12)


def test_an_overlap_within_the_slop_is_left():
    positions = correct([0, 0], [2.0 - 0.5 * SLOP, 0], 1.0, 1.0)
    np.testing.assert_array_equal(positions, [[0, 0], [2.0 - 0.5 * SLOP, 0]])


def test_engine_conserves_momentum_and_energy_in_an_isolated_collision():
    world = collisim.World(positions=[[40.0, 50.0], [60.0, 50.6]], velocities=[[6.0, 0.0], [-4.0, 0.0]],
                           radii=[1.0, 1.7], box=(0, 0, 100, 100))
    traj = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=3.0, broadphase="brute"))
    assert traj.pair_collisions.sum() == 1 and traj.wall_collisions.sum() == 0
    p = traj.momentum()
    np.testing.assert_allclose(p, np.broadcast_to(p[0], p.shape), rtol=0, atol=1e-12 * np.abs(p[0]).max())
    ke = traj.kinetic_energy()
    np.testing.assert_allclose(ke, np.full_like(ke, ke[0]), rtol=1e-12)
