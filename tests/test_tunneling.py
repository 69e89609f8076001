"""Where methods fail, measured rather than hidden: discrete detection tunnels, ccd does not.

Each lane holds one experiment, far from the others; 40 lanes sample 40 start phases of the
frame at which the contact would happen. Discrete detection sees a segment only if a frame
lands while the body overlaps it on its approach: a window of r out of the s = v·dt travelled
per frame, so the tunnelling fraction is max(0, 1 - r/s). A pair of bodies is also seen one step
ahead, while their gap is under both speculative margins (each body's travel in a step, capped
at its radius) and closes within the step: a window of r1 + r2 + min(s, m1 + m2).
"""
import numpy as np
import pytest

import collisim

PHASES = 40
RATIOS = [0.5, 1.0, 1.5, 2.0, 3.0, 5.0, 8.0, 13.0, 20.0, 40.0]   # s / r, the travel per frame in radii
FPS = 60.0
LANE = 10.0
# 40 evenly spaced phases measure a fraction to within 1/40; rounding at the window's edges
# may flip one more lane.
TOLERANCE = 2.0 / PHASES


def expected_fraction(window, travel):
    return max(0.0, 1.0 - window / travel)


def pair_window(r1, r2, travel):
    """The relative travel within which a head-on pair of equal speeds is seen (module docstring)."""
    margins = min(travel / 2, r1) + min(travel / 2, r2)
    return r1 + r2 + min(travel, margins)


def barrier_lanes(ratio, method, radius=0.5):
    """A particle per lane flying at a thin vertical segment at x = 0."""
    travel = ratio * radius
    speed = travel * FPS
    phases = (np.arange(PHASES) + 0.5) / PHASES
    y = LANE * np.arange(PHASES)
    x0 = -radius - 3.0 * travel - phases * travel      # contact between frames 3 and 4, at varying phase
    world = collisim.World(positions=np.column_stack([x0, y]), velocities=np.tile([speed, 0.0], (PHASES, 1)),
                           radii=radius, box=(-1e5, -LANE, 1e5, LANE * PHASES),
                           segments=[[0.0, -LANE / 2, 0.0, LANE * PHASES]])
    traj = collisim.simulate(collisim.Scene(world=world, fps=FPS, seconds=8 / FPS, method=method))
    return np.mean(traj.positions[-1, :, 0] > 0.0)


def pair_lanes(ratio, method, r1=0.5, r2=0.8):
    """Two particles per lane meeting head-on (equal masses, so they swap velocities)."""
    window = r1 + r2
    travel = ratio * window / 2              # relative travel per frame, in units of the mean radius
    speed = travel * FPS / 2                 # each moves half of the relative travel
    phases = (np.arange(PHASES) + 0.5) / PHASES
    y = LANE * np.arange(PHASES)
    gap = window + 3.0 * travel + phases * travel
    left = np.column_stack([-gap / 2, y])
    right = np.column_stack([gap / 2, y])
    positions = np.vstack([left, right])
    velocities = np.vstack([np.tile([speed, 0.0], (PHASES, 1)), np.tile([-speed, 0.0], (PHASES, 1))])
    world = collisim.World(positions=positions, velocities=velocities, radii=np.r_[np.full(PHASES, r1),
                           np.full(PHASES, r2)], masses=np.ones(2 * PHASES), box=(-1e5, -LANE, 1e5, LANE * PHASES))
    traj = collisim.simulate(collisim.Scene(world=world, fps=FPS, seconds=8 / FPS, method=method,
                                            broadphase="grid"))
    x = traj.positions[-1, :, 0]
    passed = x[:PHASES] > x[PHASES:]          # the left one ended on the right: they went through
    return np.mean(passed), pair_window(r1, r2, travel), travel


@pytest.mark.parametrize("ratio", RATIOS)
def test_discrete_pairs_tunnel_in_the_predicted_fraction_of_phases(ratio):
    measured, window, travel = pair_lanes(ratio, "discrete")
    assert measured == pytest.approx(expected_fraction(window, travel), abs=TOLERANCE)


def test_tunnelling_curve_for_pairs_rises_from_zero_to_almost_all():
    fractions = [pair_lanes(ratio, "discrete")[0] for ratio in (0.5, 120.0)]
    assert fractions[0] == 0.0 and fractions[1] >= 0.95


@pytest.mark.parametrize("ratio", RATIOS)
def test_discrete_barrier_tunnels_in_the_predicted_fraction_of_phases(ratio):
    assert barrier_lanes(ratio, "discrete") == pytest.approx(expected_fraction(1.0, ratio), abs=TOLERANCE)


@pytest.mark.parametrize("ratio", [0.5, 2.0, 8.0, 40.0])
def test_ccd_never_tunnels(ratio):
    assert barrier_lanes(ratio, "ccd") == 0.0
    assert pair_lanes(ratio, "ccd")[0] == 0.0
