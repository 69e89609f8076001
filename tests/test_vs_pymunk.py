"""collisim against pymunk (Chipmunk2D), the outside reference (collisim.analysis.reference.pymunk_mirror).

Each check states where the two must agree exactly (same arithmetic on the same geometry) and
where they may differ, with a tolerance derived from the step size or from the measured
run-to-run scatter of a chaotic gas. What differs and why is written up in collisim.analysis.compare.
"""
import math

import numpy as np
import pymunk
import pytest

import collisim
from collisim.analysis import metrics
from collisim.analysis.compare import DEFAULT_METHODS, compare, format_table, parse_method, rows_to_json
from collisim.analysis.reference import simulate_pymunk
from collisim.analysis.reference.pymunk_mirror import Mirror
from collisim.core.kinds import PAIR, WALL

pytestmark = pytest.mark.comparison

FPS = 60.0


def run_all(scene):
    """(ccd, discrete, pymunk) trajectories of one scene, the last two at its substeps."""
    return (collisim.simulate(scene.replace(method="ccd")), collisim.simulate(scene.replace(method="discrete")),
            simulate_pymunk(scene))


# --- the mirror is the World -------------------------------------------------------------------

def test_mirror_combines_to_the_worlds_restitution_everywhere():
    world = collisim.World([[2.0, 2.0], [5.0, 2.0]], radii=[0.3, 0.5], restitution=0.49,
                           segments=[[8.0, 1.0, 8.0, 9.0]])
    mirror = Mirror(world)
    particles = [s for s in mirror.space.shapes if isinstance(s, pymunk.Circle)]
    statics = [s for s in mirror.space.shapes if isinstance(s, pymunk.Segment)]
    assert len(statics) == 4 + 1
    # Chipmunk multiplies elasticities: every combination the gas can meet must give e itself
    for other in particles[1:] + statics:
        assert particles[0].elasticity * other.elasticity == pytest.approx(0.49, rel=1e-12)
    assert all(s.friction == 0 for s in mirror.space.shapes)
    assert all(b.moment == math.inf for b in mirror.bodies)
    assert mirror.space.collision_slop == pytest.approx(1e-3 * 0.3)


def test_pymunk_and_collisim_restitution_agree_for_pairs_and_walls():
    # e = 0.5: with e on each particle, the product rule would give 0.25 between two particles.
    # A head-on pair (one collision) and, far away, one particle flying into the right wall.
    world = collisim.World([[2.0, 2.0], [4.0, 2.0], [8.0, 8.0]], [[2.0, 0.0], [-1.0, 0.0], [6.0, 0.0]],
                           radii=0.5, masses=[1.0, 2.0, 1.0], box=(0, 0, 10, 10), restitution=0.5)
    scene = collisim.Scene(world=world, fps=FPS, seconds=0.5)
    _, discrete, mirror = run_all(scene)
    for traj in (discrete, mirror):
        assert traj.pair_collisions.sum() == 1 and traj.wall_collisions.sum() == 1
        v = traj.velocities[-1, :, 0]
        # 1D collisions do not depend on when they were detected: exact in both engines
        assert (v[1] - v[0]) == pytest.approx(-0.5 * (-1.0 - 2.0), rel=1e-12)
        assert v[0] + 2 * v[1] == pytest.approx(2.0 - 2.0, abs=1e-12)      # momentum
        assert v[2] == pytest.approx(-0.5 * 6.0, rel=1e-12)


# --- single bounce ------------------------------------------------------------------------------

def bounces(traj, wall, gravity=(0.0, -9.8)):
    """(times, rebound speeds) of the bounces of particle 0 off one wall (0..3 = left, right,
    bottom, top): the velocity away from the wall at the first frame after each event, carried
    back to the event's time under gravity."""
    chosen = (traj.events.kind == WALL) & (traj.events.j == wall)
    time, frame = traj.events.time[chosen], metrics.event_frames(traj)[chosen]
    axis, away = wall // 2, (1.0 if wall % 2 == 0 else -1.0)
    velocity = traj.velocities[frame, 0, axis] - gravity[axis] * (traj.times[frame] - time)
    return time, away * velocity


@pytest.fixture(scope="module")
def single_bounce():
    scene = collisim.load_scene("single_bounce")
    return scene, run_all(scene), simulate_pymunk(scene, substeps=8)


def test_single_bounce_same_sequence_of_walls(single_bounce):
    _, runs, pymunk8 = single_bounce
    sequences = [tuple(t.events.j[t.events.kind == WALL]) for t in (*runs, pymunk8)]
    assert len(set(sequences)) == 1 and len(sequences[0]) == 5


def test_single_bounce_discrete_is_at_most_one_step_late(single_bounce):
    scene, (ccd, discrete, _), _ = single_bounce
    dt = 1.0 / scene.fps
    for wall in (1, 2):
        exact_time, exact_speed = bounces(ccd, wall)
        time, speed = bounces(discrete, wall)
        # discrete detection: the bounce is seen at the end of the step it happened in
        assert np.all(time - exact_time >= -1e-12) and np.all(time - exact_time <= dt + 1e-12)
        # the response keeps the energy, so the speed is the exact one at the reflected
        # position, which is at most one step of gravity past the contact
        np.testing.assert_allclose(speed, exact_speed, atol=9.8 * dt)


@pytest.mark.parametrize("substeps", [1, 8])
def test_single_bounce_pymunk_within_its_integrator_error(single_bounce, substeps):
    scene, (ccd, _, pymunk1), pymunk8 = single_bounce
    mirror = pymunk1 if substeps == 1 else pymunk8
    dt = 1.0 / scene.fps / substeps
    exact_time, exact_speed = bounces(ccd, 2)
    time, speed = bounces(mirror, 2)
    # Chipmunk's bounce targets the velocity of the previous step (before this step's gravity)
    # and absorbs this step's gravity in the impulse: the rebound is within one step of gravity
    np.testing.assert_allclose(speed, exact_speed, atol=9.8 * dt)
    # Timing: the first fall is seen up to one step late plus the half-step lag of semi-implicit
    # Euler (2 dt); every later flight lasts 2u/g + dt by Euler, plus up to one step of
    # detection, with u off by <= g dt (2 dt): <= 4 dt more per flight. The errors accumulate
    # (the n-th bounce is ~1.1 n steps late, measured) but shrink with the step: first order.
    bound = 2 * dt + 4 * dt * np.arange(len(time))
    assert np.all(np.abs(time - exact_time) <= bound)
    # sideways: no gravity along x, so the elastic reflection is exact in every engine
    np.testing.assert_allclose(bounces(mirror, 1)[1], bounces(ccd, 1)[1], rtol=1e-12)


def test_single_bounce_energy(single_bounce):
    scene, (ccd, discrete, pymunk1), pymunk8 = single_bounce
    world = scene.world
    # collisim integrates constant acceleration exactly and its wall response keeps the energy
    assert metrics.energy_drift(ccd, world) < 1e-12
    assert metrics.energy_drift(discrete, world) < 1e-12
    # pymunk's semi-implicit Euler swings the energy by O(g·dt) in speed: m·v·g·dt / E ~ 3 %
    # at 60 fps, and first order in dt (8 substeps: about 8 times less)
    swing = [np.abs(metrics.mechanical_energy(t, world) / metrics.mechanical_energy(t, world)[0] - 1).max()
             for t in (pymunk1, pymunk8)]
    v = math.sqrt(2 * metrics.mechanical_energy(ccd, world)[0] / world.masses[0])
    scale = world.masses[0] * v * 9.8 / FPS / metrics.mechanical_energy(ccd, world)[0]
    assert swing[0] < 2 * scale
    assert swing[1] < 2 * scale / 8


# --- two bodies: an isolated contact -------------------------------------------------------------

def touching_pair(restitution=1.0, overlap=1e-9):
    """two_bodies' circles meeting obliquely: they overlap by `overlap` (relative) at the end
    of the first step, so both discrete engines see the contact with the same geometry."""
    base = collisim.load_scene("two_bodies").world
    reach = base.radii.sum()
    normal = np.array([math.cos(0.6), math.sin(0.6)])
    end = np.array([[8.0, 4.5], [8.0, 4.5] + normal * reach * (1 - overlap)])
    start = end - base.velocities / FPS
    world = collisim.World(start, base.velocities, base.radii, base.masses, box=base.box,
                           restitution=restitution)
    return collisim.Scene(world=world, fps=FPS, seconds=1.0 / FPS), normal


def closed_form(world, normal):
    """The video's two-body formula with restitution along the line of centres."""
    (m1, m2), (v1, v2) = world.masses, world.velocities
    approach = (v2 - v1) @ normal
    impulse = -(1 + world.restitution) * approach / (1 / m1 + 1 / m2)
    return np.array([v1 - impulse / m1 * normal, v2 + impulse / m2 * normal])


@pytest.mark.parametrize("restitution", [1.0, 0.6])
def test_isolated_contact_same_response(restitution):
    scene, normal = touching_pair(restitution)
    ccd, discrete, mirror = run_all(scene)
    assert discrete.pair_collisions[1] == mirror.pair_collisions[1] == ccd.pair_collisions[1] == 1
    # one contact, whose impulse pymunk's solver reaches in its first iteration; collisim takes
    # the normal where the bodies touch, pymunk at the step's end, 1e-9 past it
    np.testing.assert_allclose(mirror.velocities[1], discrete.velocities[1], rtol=0, atol=1e-7)
    # ccd and the closed form use the normal at the exact touching instant, which differs from
    # the one at the step end by the 1e-9 overlap: agreement to ~1e-9 of the speeds
    expected = closed_form(scene.world, normal)
    np.testing.assert_allclose(ccd.velocities[1], expected, atol=1e-7)
    np.testing.assert_allclose(discrete.velocities[1], expected, atol=1e-7)
    # the impulse the events report is the same physical quantity
    pair_impulse = [t.events.impulse[t.events.kind == PAIR][0] for t in (ccd, discrete, mirror)]
    np.testing.assert_allclose(pair_impulse, pair_impulse[0], rtol=1e-7)


def test_two_bodies_conserve_kinetic_energy_in_every_engine():
    scene = collisim.load_scene("two_bodies")
    for traj in run_all(scene):
        # no gravity, e = 1: isolated elastic contacts and walls keep kinetic energy exactly
        ke = traj.kinetic_energy()
        assert abs(ke[-1] / ke[0] - 1) < 1e-12
        assert traj.pair_collisions.sum() >= 2


# --- a gas: statistics ---------------------------------------------------------------------------

@pytest.fixture(scope="module")
def gas():
    scene = collisim.load_scene("particles_250")     # 250 particles, three sizes, no gravity, 10 s
    return scene, dict(zip(("ccd", "discrete", "pymunk"), run_all(scene)))


# Relaxed speeds: t >= 5 s (about 15 collisions per particle), one snapshot a second: a particle
# collides ~3 times a second, so the 6 snapshots x 250 particles are close to independent.
RELAXED, EVERY = 5.0, 1.0
SAMPLES = 6 * 250
KS_TWO_SAMPLE_99 = 1.63 * math.sqrt(2 / SAMPLES)    # 99 % critical values of the KS statistic
KS_ONE_SAMPLE_99 = 1.63 / math.sqrt(SAMPLES)


def test_gas_speed_distributions_agree(gas):
    _, runs = gas
    speeds = {name: metrics.sampled_speeds(t, RELAXED, EVERY) for name, t in runs.items()}
    assert all(len(s) == SAMPLES for s in speeds.values())
    for name in ("ccd", "discrete"):
        assert metrics.speed_distribution_ks(speeds[name], speeds["pymunk"]) < KS_TWO_SAMPLE_99


def test_gas_relaxes_to_maxwell_boltzmann(gas):
    scene, runs = gas
    mean_energy = runs["ccd"].kinetic_energy()[0] / scene.world.n
    law = lambda v: metrics.maxwell_boltzmann_cdf(v, mean_energy, scene.world.masses)  # noqa: E731
    # the start (uniform speeds, one law for all masses) is far from it: the test can tell
    assert metrics.ks_statistic(np.linalg.norm(scene.world.velocities, axis=1), law) > 0.15
    for name, traj in runs.items():
        assert metrics.ks_statistic(metrics.sampled_speeds(traj, RELAXED, EVERY), law) < KS_ONE_SAMPLE_99, name


# Over 12 seeds of this gas (10 s each), relative to ccd: pair collisions pymunk -3.4 % (scatter
# 1.7 %), discrete -1.7 % (2.2 %); wall pressure pymunk -1.0 % (1.4 %), discrete -2.6 % (1.9 %).
# The bias is the first-order shrinking of the effective diameter by late detection (see
# collisim.analysis.compare); bias + 3 scatter stays under 10 %.
RATE_TOLERANCE = 0.10


def test_gas_collision_rate_and_pressure(gas):
    scene, runs = gas
    exact = runs["ccd"]
    for name in ("discrete", "pymunk"):
        traj = runs[name]
        assert traj.pair_collisions.sum() / exact.pair_collisions.sum() == pytest.approx(1, abs=RATE_TOLERANCE), name
        pressure = metrics.wall_pressure(traj, scene.world) / metrics.wall_pressure(exact, scene.world)
        assert pressure == pytest.approx(1, abs=RATE_TOLERANCE), name


def test_gas_energy(gas):
    scene, runs = gas
    # collisim's impulses and overlap removal change no kinetic energy: round-off only.
    for name in ("discrete", "ccd"):
        assert metrics.energy_drift(runs[name], scene.world) < 1e-9, name
    # No gravity: Chipmunk's slop and bias correct positions only, and an isolated contact is
    # solved exactly, so pymunk's kinetic energy moves only through simultaneous contacts, which
    # its iterative solver resolves approximately. In this dilute gas a few per run: measured
    # 3e-14 to 6e-5 depending on the start; 1e-3 is ten times the worst seen on a dense gas.
    assert metrics.energy_drift(runs["pymunk"], scene.world) < 1e-3


# --- tunnelling ----------------------------------------------------------------------------------

PHASES = 40
LANE = 10.0


def barrier_lanes(travel_in_radii, radius=0.5):
    """A particle per lane flying at one thin vertical segment at x = 0, contact at 40 phases."""
    travel = travel_in_radii * radius
    phases = (np.arange(PHASES) + 0.5) / PHASES
    x0 = -radius - 3.0 * travel - phases * travel
    world = collisim.World(np.column_stack([x0, LANE * np.arange(PHASES)]), np.tile([travel * FPS, 0.0], (PHASES, 1)),
                           radii=radius, box=(-1e5, -LANE, 1e5, LANE * PHASES),
                           segments=[[0.0, -LANE / 2, 0.0, LANE * PHASES]])
    return collisim.Scene(world=world, fps=FPS, seconds=8 / FPS)


def pair_lanes(travel_in_windows, r1=0.5, r2=0.8):
    """Two particles per lane meeting head-on at 40 phases (equal masses)."""
    window = r1 + r2
    travel = travel_in_windows * window                  # relative travel per frame
    phases = (np.arange(PHASES) + 0.5) / PHASES
    y = LANE * np.arange(PHASES)
    gap = window + 3.0 * travel + phases * travel
    positions = np.vstack([np.column_stack([-gap / 2, y]), np.column_stack([gap / 2, y])])
    each = np.tile([travel * FPS / 2, 0.0], (PHASES, 1))       # each moves half the relative travel
    velocities = np.vstack([each, -each])
    world = collisim.World(positions, velocities, radii=np.r_[np.full(PHASES, r1), np.full(PHASES, r2)],
                           masses=np.ones(2 * PHASES), box=(-1e5, -LANE, 1e5, LANE * PHASES))
    return collisim.Scene(world=world, fps=FPS, seconds=8 / FPS, broadphase="grid")


@pytest.mark.parametrize("travel", [0.5, 1.5, 3.0, 13.0])
def test_barrier_tunnelling_is_the_same_in_pymunk_and_discrete(travel):
    scene = barrier_lanes(travel)
    ccd, discrete, mirror = run_all(scene)
    through = [t.positions[-1, :, 0] > 0 for t in (ccd, discrete, mirror)]
    # both detect at step ends only, with the same positions (p += v·dt): the same lanes tunnel
    np.testing.assert_array_equal(through[1], through[2])
    # and as many as the contact window predicts: max(0, 1 - r/s) of the phases, +-1 lane
    assert abs(through[1].sum() - PHASES * max(0.0, 1 - 1 / travel)) <= 1
    assert not through[0].any()      # ccd finds every contact in time
    for traj, passed in zip((ccd, discrete, mirror), through):
        assert metrics.missed_segment_crossings(traj, scene.world).sum() == passed.sum()


@pytest.mark.parametrize("travel", [0.75, 1.5, 6.5])
def test_pair_tunnelling_is_the_same_in_pymunk_and_discrete(travel):
    scene = pair_lanes(travel)
    ccd, discrete, mirror = run_all(scene)
    through = [t.positions[-1, :PHASES, 0] > t.positions[-1, PHASES:, 0] for t in (ccd, discrete, mirror)]
    # collisim's discrete method also looks one step ahead (speculative contacts), pymunk's only
    # at overlaps: it misses no pair that pymunk catches, and at a travel of a few radii, fewer
    assert not (through[1] & ~through[2]).any()
    if travel > 1.0:
        assert through[1].sum() < through[2].sum()
    assert not through[0].any()
    for traj, passed in zip((ccd, discrete, mirror), through):
        assert metrics.missed_collisions(traj).sum() == passed.sum()


# --- compare -------------------------------------------------------------------------------------

def test_compare_rows_table_and_json():
    rows = compare(collisim.load_scene("two_bodies"), seconds=1.0)
    assert [r["label"] for r in rows] == list(DEFAULT_METHODS)
    by_label = {r["label"]: r for r in rows}
    assert by_label["ccd"]["position_error"] == 0 and by_label["ccd"]["missed_pairs"] == 0
    assert all(r["error"] is None and r["energy_drift"] < 1e-9 for r in rows)
    table = format_table(rows).splitlines()
    assert len(table) == 2 + len(rows) and "[radii]" in table[1]
    assert '"discrete x8"' in rows_to_json(rows)


def test_compare_runs_every_panel_and_reports_a_method_that_cannot_run():
    uneven = collisim.World([[2.0, 2.0], [6.0, 2.0]], [[1.0, 0.0], [-1.0, 0.0]], radii=0.5,
                            accelerations=[[0.0, -1.0], [0.0, -2.0]])   # ccd needs one gravity
    even = collisim.World([[2.0, 2.0]], [[1.0, 0.0]], radii=0.5)
    panels = [collisim.Panel(collisim.Scene(world=w, fps=30, seconds=0.5), title) for w, title in
              ((uneven, "uneven"), (even, "even"))]
    rows = compare(collisim.Scene(panels=panels, fps=30, seconds=0.5), methods=["ccd", "pymunk x2"])
    # each distinct world is titled by what it holds
    assert [r["label"] for r in rows] == ["2 particles: ccd", "2 particles: pymunk x2",
                                          "1 particle: ccd", "1 particle: pymunk x2"]
    assert rows[0]["error"] and rows[0]["energy_drift"] is None and rows[1]["position_error"] is None
    assert rows[2]["error"] is None and "could not run" in format_table(rows)


@pytest.mark.parametrize("label", ["rk4", "discrete x0", "ccd x2"])
def test_compare_rejects_unknown_methods_in_one_line(label):
    with pytest.raises(ValueError, match="unknown method|substeps") as error:
        parse_method(label)
    assert "\n" not in str(error.value)


def test_compare_accepts_a_comma_separated_string_and_checks_its_input():
    scene = collisim.load_scene("single_bounce")
    rows = compare(scene, methods="ccd, discrete x2", seconds=0.5)
    assert [r["label"] for r in rows] == ["ccd", "discrete x2"]
    for bad in (dict(seconds=-1.0), dict(horizon=float("nan")), dict(methods=[])):
        with pytest.raises(ValueError):
            compare(scene, **bad)


def test_compare_cli_prints_a_table_for_a_scene_of_chapters_and_panels(cli):
    result = cli("compare", "tunneling", "--seconds", "1", "--methods", "discrete x1", "ccd")
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert any(line.startswith("4 particles, 1 segment: ccd") for line in lines)
    assert any(line.startswith("6 particles: discrete x1") for line in lines)
    json_result = cli("compare", "two_bodies", "--seconds", "1", "--json")
    import json
    rows = json.loads(json_result.stdout)
    assert {row["method"] for row in rows} == {"discrete x1", "discrete x8", "ccd", "pymunk x1"}
