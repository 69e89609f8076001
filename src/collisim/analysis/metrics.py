"""Accuracy measurements of a recorded Trajectory: small pure numpy functions.

Shared by `collisim compare` and `collisim bench accuracy`. Shapes: F samples (frames + 1),
n particles, m thin segments. Every function reads the trajectory (and the World it started
from, for the box, the accelerations and the segments) and changes nothing.
"""
from __future__ import annotations

import numpy as np

from ..core.kinds import CIRCLE, N_WALLS, PAIR, SUPPORT, WALL

# An event at time t belongs to the interval (t_{f-1}, t_f]. Discrete steps stamp events with
# step_count·dt, which can differ from f/fps in the last bit: this slack (in frames) absorbs it.
_EVENT_TIME_SLACK = 1e-9


# --- energy and momentum -----------------------------------------------------------------------

def potential_energy(traj, world) -> np.ndarray:
    """(F,) potential energy of every particle's constant acceleration a_i (force m_i·a_i).

    U = Σ m_i · (−a_i · (x_i − x_floor,i)), where x_floor,i is the corner of the box (shrunk by
    r_i) lowest along a_i, so U >= 0 for every particle inside the box (under gravity (0, −g):
    m·g·(y − ymin − r)). Measuring from the floor makes E_0 the energy the motion really has,
    so a relative drift is not diluted by an arbitrary height reference.
    """
    a = world.accelerations                                       # (n, 2)
    r = world.radii[:, None]
    low, high = world.box[:2] + r, world.box[2:] - r               # (n, 2) each
    floor = np.where(a > 0, high, low)
    depth = -np.einsum("nk,fnk->fn", a, traj.positions - floor)    # (F, n), >= 0 inside
    return depth @ world.masses


def mechanical_energy(traj, world) -> np.ndarray:
    """(F,) kinetic plus potential energy."""
    return traj.kinetic_energy() + potential_energy(traj, world)


def energy_drift(traj, world) -> float:
    """|E_end − E_0| / E_0 for the total mechanical energy (see potential_energy)."""
    energy = mechanical_energy(traj, world)
    return _relative_change(energy[-1] - energy[0], energy[0])


def momentum_drift(traj) -> float:
    """|P_end − P_0| / Σ m_i·|v_i(0)|: the change of total momentum relative to the momentum
    the particles carry. Walls, segments and accelerations change momentum legitimately, so this
    only means something for a world where nothing but pair collisions act (the caller decides)."""
    momentum = traj.momentum()                                     # (F, 2)
    scale = float(np.sum(traj.masses * np.linalg.norm(traj.velocities[0], axis=1)))
    return _relative_change(np.linalg.norm(momentum[-1] - momentum[0]), scale)


def _relative_change(change, scale) -> float:
    change = abs(float(change))
    if scale == 0:
        return 0.0 if change == 0 else float("inf")
    return change / abs(float(scale))


# --- geometry: overlaps, escapes ---------------------------------------------------------------

def overlaps(traj) -> np.ndarray:
    """(F,) the largest pair overlap in each frame, its depth over the smaller body's radius
    (a polygon's: its bounding circle's), 0 if none. For circles the depth is r_i + r_j − d; with
    polygons it is the narrow phase's (narrowphase.registry.contacts, at each frame's angles).

    Candidates come from the grid broad phase per frame, so the cost is about linear in n.
    """
    from ..broadphase import make

    radii = traj.radii
    worst = np.zeros(len(traj.times))
    if len(radii) < 2:
        return worst
    if np.any(traj.world.shapes != CIRCLE):
        return _shape_overlaps(traj, worst)
    grid = make("grid")
    for f, positions in enumerate(traj.positions):
        pairs = grid.pairs(positions - radii[:, None], positions + radii[:, None])
        if len(pairs):
            i, j = pairs[:, 0], pairs[:, 1]
            distance = np.linalg.norm(positions[j] - positions[i], axis=1)
            depth = (radii[i] + radii[j] - distance) / np.minimum(radii[i], radii[j])
            worst[f] = max(float(depth.max()), 0.0)
    return worst


def _shape_overlaps(traj, worst) -> np.ndarray:
    """overlaps for a world with polygons: every frame's deepest contact, in radii."""
    from ..queries.contacts import contacts

    radii = traj.world.radii
    for f in range(len(traj.times)):
        found = contacts(traj.world, traj.positions[f], traj.angles[f])
        if len(found["depths"]):
            i, j = found["pairs"][:, 0], found["pairs"][:, 1]
            worst[f] = max(float(np.max(found["depths"] / np.minimum(radii[i], radii[j]))), 0.0)
    return worst


def max_overlap(traj) -> float:
    """The largest pair overlap over all frames, in radii of the smaller body (overlaps)."""
    return float(overlaps(traj).max()) if len(traj.times) else 0.0


def outside(traj, world, depth: float = 1.0) -> tuple:
    """(count at the last frame, count ever) of particles that left the box.

    A particle counts when its circle reaches beyond a wall by more than depth × its radius:
    with the default depth 1 its centre has left the box (the particle escaped, half of it at
    least); depth 0 counts any part of a circle beyond a wall, which every discrete engine
    that lets contacts overlap for a step does at nearly every wall contact.
    """
    r = traj.radii[:, None]
    beyond_low = world.box[:2] - (traj.positions - r)              # (F, n, 2) > 0: past xmin/ymin
    beyond_high = (traj.positions + r) - world.box[2:]
    reach = np.maximum(beyond_low, beyond_high).max(axis=2)        # (F, n)
    out = reach > depth * traj.radii + 1e-12 * np.abs(world.box).max()
    return int(out[-1].sum()), int(out.any(axis=0).sum())


# --- tunnelling --------------------------------------------------------------------------------

def event_frames(traj) -> np.ndarray:
    """(k,) the frame f of each event: the one whose interval (t_{f-1}, t_f] holds its time."""
    if len(traj.times) < 2:
        return np.zeros(len(traj.events), np.intp)
    slack = _EVENT_TIME_SLACK * (traj.times[1] - traj.times[0])
    return np.searchsorted(traj.times, traj.events.time - slack, side="left")


def missed_collisions(traj) -> np.ndarray:
    """(F,) per frame: pairs whose circles met between samples without a registered collision.

    A pair (i, j) counts in frame f when
      * the straight path of their relative position from t_{f-1} to t_f comes closer than
        r_i + r_j, and its closest point lies strictly inside the interval: the pair was
        approaching at t_{f-1} and separating at t_f, so it went through the contact distance
        and back out within the frame; and
      * neither i nor j registered any collision (with anything) in (t_{f-1}, t_f].
    Without a registered collision a particle moves on the parabola of its own acceleration,
    so under a uniform acceleration the relative motion is exactly the straight line judged
    here and every count is a real pass-through: circles that overlapped, or crossed, and were
    never pushed back. That includes a pass-through that ends overlapping, or that the discrete
    overlap removal parks at contact on the far side. A pair where one of the two registered a
    collision is not judged (its path bent within the frame, and the chord could cut a corner),
    so the count is a lower bound when particles collide several times within a frame. A pair
    that touches at a sample, or approaches into an overlap found at the next sample, has its
    closest point at an end of the interval and is not counted. Frame 0 is always 0.
    """
    n, count = len(traj.radii), np.zeros(len(traj.times), np.int64)
    if n < 2 or len(traj.times) < 2:
        return count
    from ..broadphase import make

    grid, radii = make("grid"), traj.radii
    busy = _busy_particles(traj)
    for f in range(1, len(traj.times)):
        before, after = traj.positions[f - 1], traj.positions[f]
        swept_lo = np.minimum(before, after) - radii[:, None]
        swept_hi = np.maximum(before, after) + radii[:, None]
        pairs = grid.pairs(swept_lo, swept_hi)
        if len(pairs):
            count[f] = _passed_through(before, after, radii, pairs, busy[f - 1] if busy is not None else None)
    return count


def _busy_particles(traj):
    """(F-1, n) bool: particle took part in a registered collision in interval f (None if none)."""
    if len(traj.events) == 0:
        return None
    frames = event_frames(traj) - 1
    busy = np.zeros((len(traj.times) - 1, len(traj.radii)), bool)
    ok = (frames >= 0) & (frames < len(busy))
    busy[frames[ok], traj.events.i[ok]] = True
    pair = ok & (traj.events.kind == PAIR)
    busy[frames[pair], traj.events.j[pair]] = True
    return busy


def _passed_through(before, after, radii, pairs, busy) -> int:
    i, j = pairs[:, 0], pairs[:, 1]
    if busy is not None:
        quiet = ~(busy[i] | busy[j])
        i, j = i[quiet], j[quiet]
    reach = radii[i] + radii[j]
    start = before[j] - before[i]
    motion = (after[j] - after[i]) - start
    speed2 = np.einsum("kd,kd->k", motion, motion)
    moving = speed2 > 0
    s = -np.einsum("kd,kd->k", start, motion) / np.where(moving, speed2, 1.0)  # closest approach
    inside = moving & (s > 0.0) & (s < 1.0)
    closest = np.linalg.norm(start + np.clip(s, 0.0, 1.0)[:, None] * motion, axis=1)
    return int(np.count_nonzero(inside & (closest < reach)))


def missed_segment_crossings(traj, world) -> np.ndarray:
    """(F,) per frame: particles whose centre crossed a thin segment between samples.

    A crossing is a strict change of side of a segment's line between t_{f-1} and t_f where the
    straight path between the two samples meets the line within the segment (end points
    included). A segment handled correctly never lets a centre through, so every crossing is a
    miss, whether or not the method registered a collision with it (a discrete method may see
    the contact after the centre has passed and let it go on). A particle that crosses several
    segments in one frame counts once. Frame 0 is always 0.
    """
    count = np.zeros(len(traj.times), np.int64)
    if len(world.segments) == 0 or len(traj.times) < 2:
        return count
    before, after = traj.positions[:-1], traj.positions[1:]                 # (F-1, n, 2)
    crossed = np.zeros(before.shape[:2], bool)
    for x0, y0, x1, y1 in world.segments:
        a, along = np.array([x0, y0]), np.array([x1 - x0, y1 - y0])
        side_before = _cross(along, before - a)
        side_after = _cross(along, after - a)
        flips = side_before * side_after < 0
        t = side_before / np.where(flips, side_before - side_after, 1.0)    # where the path meets the line
        meet = before + t[..., None] * (after - before)
        u = ((meet - a) @ along) / max(float(along @ along), 1e-300)        # position along the segment
        crossed |= flips & (u >= 0.0) & (u <= 1.0)
    count[1:] = crossed.sum(axis=1)
    return count


def _cross(u, v):
    """z of the 2D cross product u × v, for v (..., 2)."""
    return u[0] * v[..., 1] - u[1] * v[..., 0]


# --- walls -------------------------------------------------------------------------------------

def wall_pressure(traj, world=None) -> float:
    """Mean pressure on the box of `world` (default: the trajectory's): total wall impulse /
    (duration × perimeter), in mass/time² (force per unit length of wall, the 2D pressure).
    The walls' impulse is that of the collisions with them and of their support of the bodies
    resting on them (kinds.SUPPORT), so a box holding a body at rest feels its weight."""
    xmin, ymin, xmax, ymax = (world or traj.world).box
    duration = float(traj.times[-1] - traj.times[0])
    if duration <= 0:
        return 0.0
    kind, j = traj.events.kind, traj.events.j
    on_walls = (kind == WALL) | ((kind == SUPPORT) & (j < N_WALLS))
    return float(traj.events.impulse[on_walls].sum() / (duration * 2 * ((xmax - xmin) + (ymax - ymin))))


# --- agreement between runs --------------------------------------------------------------------

def position_error(traj, reference, at_seconds: float) -> float:
    """RMS over particles of |x − x_ref| / r at the frames of both nearest `at_seconds`.

    In radii: 1 means the two runs have particles a radius apart on average.
    """
    if traj.positions.shape[1] != reference.positions.shape[1]:
        raise ValueError(f"trajectories of {traj.positions.shape[1]} and {reference.positions.shape[1]} "
                         f"particles cannot be compared")
    f = int(np.argmin(np.abs(traj.times - at_seconds)))
    g = int(np.argmin(np.abs(reference.times - at_seconds)))
    apart = np.linalg.norm(traj.positions[f] - reference.positions[g], axis=1) / traj.radii
    return float(np.sqrt(np.mean(apart ** 2))) if len(apart) else 0.0


def sampled_speeds(traj, start_seconds: float = 0.0, every_seconds: float = 0.0) -> np.ndarray:
    """Speeds of all particles in the frames from start_seconds on, one frame every
    `every_seconds` (0: every frame), flattened: (frames used × n,)."""
    frames = np.flatnonzero(traj.times >= start_seconds - 1e-12)
    if every_seconds > 0 and len(traj.times) > 1:
        stride = max(1, int(round(every_seconds / (traj.times[1] - traj.times[0]))))
        frames = frames[::stride]
    return np.linalg.norm(traj.velocities[frames], axis=2).ravel()


def speed_distribution_ks(speeds_a, speeds_b) -> float:
    """Two-sample Kolmogorov–Smirnov statistic: the largest gap between the two empirical CDFs."""
    a, b = np.sort(np.ravel(speeds_a)), np.sort(np.ravel(speeds_b))
    if len(a) == 0 or len(b) == 0:
        raise ValueError("speed_distribution_ks needs two non-empty samples")
    points = np.concatenate([a, b])
    gap = np.searchsorted(a, points, side="right") / len(a) - np.searchsorted(b, points, side="right") / len(b)
    return float(np.abs(gap).max())


def ks_statistic(samples, cdf) -> float:
    """One-sample Kolmogorov–Smirnov statistic of samples against a CDF (a vectorised function)."""
    x = np.sort(np.ravel(samples))
    if len(x) == 0:
        raise ValueError("ks_statistic needs a non-empty sample")
    expected = cdf(x)
    rank = np.arange(1, len(x) + 1) / len(x)
    return float(max((rank - expected).max(), (expected - (rank - 1.0 / len(x))).max()))


def maxwell_boltzmann_cdf(speeds, mean_kinetic_energy: float, masses) -> np.ndarray:
    """CDF of the speed of a particle picked at random from a 2D gas in equilibrium.

    In 2D each particle holds kT on average (½kT per degree of freedom), so
    kT = mean_kinetic_energy per particle, and a particle of mass m has the Rayleigh speed law
    P(|v| <= s) = 1 − exp(−m·s² / (2kT)). With several masses the law is the average of the
    particles' Rayleigh CDFs (for equal masses: one Rayleigh with σ² = kT/m).
    speeds: (k,) -> (k,)
    """
    speeds = np.asarray(speeds, np.float64)
    masses = np.ravel(np.asarray(masses, np.float64))
    if mean_kinetic_energy <= 0:
        raise ValueError(f"mean kinetic energy must be > 0, got {mean_kinetic_energy}")
    kinds, weight = np.unique(masses, return_counts=True)      # a few species, not n exponentials
    exponent = np.multiply.outer(speeds ** 2, kinds) / (2.0 * mean_kinetic_energy)
    return (1.0 - np.exp(-exponent)) @ (weight / len(masses))
