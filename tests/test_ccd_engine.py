"""Method ccd through the engine: exact, sampled at frame times, never tunnelling."""
import hashlib

import numpy as np
import pytest

import collisim
from collisim.engine import concatenate, stream
from collisim.analysis import metrics
from collisim.engine.ccd import simulate_events
from collisim.gas import lattice_gas


def one_particle(velocity, method, gravity=(0.0, 0.0), seconds=1.0, position=(5.0, 5.0), box=(0, 0, 10, 10)):
    world = collisim.World(positions=[position], velocities=[velocity], radii=0.5, box=box, gravity=gravity)
    return collisim.simulate(collisim.Scene(world=world, fps=60, seconds=seconds, method=method))


@pytest.mark.parametrize("method", ["discrete", "ccd"])
def test_a_particle_at_a_million_units_per_second_stays_in_the_box(method):
    traj = one_particle([1e6 * np.cos(0.3), 1e6 * np.sin(0.3)], method)
    p = traj.positions[:, 0]
    assert np.all(p >= 0.5 - 1e-9) and np.all(p <= 9.5 + 1e-9)
    np.testing.assert_allclose(np.hypot(*traj.velocities[:, 0].T), 1e6, rtol=1e-9)


def apex_heights(traj, g):
    """The apex each state is heading for: y + vy²/2g (constant for an exact elastic bounce)."""
    y, vy = traj.positions[:, 0, 1], traj.velocities[:, 0, 1]
    return y + vy ** 2 / (2 * g)


def test_ccd_keeps_the_apex_to_1e9_over_100_bounces():
    g = 9.81
    # a drop from 5 - 0.5 = 4.5 above the floor contact: one bounce every 2·sqrt(2h/g) ≈ 1.92 s
    traj = one_particle([0.0, 0.0], "ccd", gravity=(0, -g), seconds=195.0)
    assert traj.wall_collisions.sum() >= 100
    apex = apex_heights(traj, g)
    np.testing.assert_allclose(apex, np.full_like(apex, 5.0), rtol=1e-9)


def test_discrete_bounce_height_is_bounded_by_the_frame_sampling():
    """The energy-consistent wall reflection keeps the apex the state is heading for; what
    drifts is only where the frames sample the flight, never more than one frame's worth."""
    g, fps = 9.81, 60
    traj = one_particle([0.0, 0.0], "discrete", gravity=(0, -g), seconds=195.0)
    apex = apex_heights(traj, g)
    drift = np.abs(apex - 5.0).max()
    assert drift < 1e-9 * 5.0   # measured ~1e-14: the reflection makes and loses no energy
    heights = traj.positions[:, 0, 1]
    between = np.split(heights, np.flatnonzero(traj.wall_collisions) )[1:-1]
    sampled_apex = np.array([segment.max() for segment in between if len(segment)])
    assert len(sampled_apex) >= 99
    # a frame lands within dt/2 of the true apex: the sampled apex is at most g(dt/2)²/2 low
    assert np.all(5.0 - sampled_apex <= g * (0.5 / fps) ** 2 / 2 + 1e-9)


@pytest.fixture(scope="module")
def gas():
    scene = collisim.load_scene("particles_250").replace(method="ccd", seconds=10.0)
    return scene, collisim.simulate(scene)


def test_ccd_gas_conserves_energy_and_never_overlaps(gas):
    scene, traj = gas
    ke = traj.kinetic_energy()
    assert np.abs(ke / ke[0] - 1).max() <= 1e-10
    from collisim.broadphase import find_pairs
    worst = 0.0
    for positions in traj.positions:
        lo, hi = positions - traj.radii[:, None], positions + traj.radii[:, None]
        pairs = find_pairs("grid", lo, hi)
        d = np.hypot(*(positions[pairs[:, 0]] - positions[pairs[:, 1]]).T)
        reach = traj.radii[pairs[:, 0]] + traj.radii[pairs[:, 1]]
        worst = max(worst, np.max((reach - d) / traj.radii[pairs].min(axis=1), initial=0.0))
    assert worst <= 1e-9
    assert traj.pair_collisions.sum() > 1000 and len(traj.events) == traj.collisions.sum()


def test_ccd_events_carry_impulses_that_give_the_wall_pressure(gas):
    scene, traj = gas
    walls = traj.events.kind == 0
    # every wall hit reverses a normal velocity: impulse = 2·m·|v_n| > 0, at a point on the box
    assert np.all(traj.events.impulse[walls] > 0)
    xmin, ymin, xmax, ymax = scene.world.box
    x, y = traj.events.point[walls].T
    on_edge = np.isclose(x, xmin) | np.isclose(x, xmax) | np.isclose(y, ymin) | np.isclose(y, ymax)
    assert on_edge.all()
    # Hard-disk gas: P = (N kT / A) · Z(η), kT = mean kinetic energy per particle (two degrees of
    # freedom), A the area the centres can reach, Z = (1 + η²/8)/(1 - η)² Henderson's equation of
    # state for packing fraction η. Measured within 2 %; 5 % allows for the size mixture and noise.
    r = traj.radii.mean()
    area = (xmax - xmin - 2 * r) * (ymax - ymin - 2 * r)
    eta = np.pi * np.sum(traj.radii ** 2) / ((xmax - xmin) * (ymax - ymin))
    henderson = (1 + eta ** 2 / 8) / (1 - eta) ** 2
    expected = traj.kinetic_energy()[0] / area * henderson
    assert metrics.wall_pressure(traj) == pytest.approx(expected, rel=0.05)


def test_ccd_blocks_lose_nothing_at_block_boundaries(gas):
    scene, traj = gas
    w = scene.world
    whole = simulate_events(w.positions, w.velocities, w.gravity, w.radii, w.masses, w.box, w.restitution,
                            w.segments, 1 / scene.fps, 70)
    # the engine streams blocks of 64 frames from one event loop: the same run as one call
    np.testing.assert_array_equal(traj.positions[:71], whole.positions)
    np.testing.assert_array_equal(traj.velocities[:71], whole.velocities)
    assert traj.pair_collisions[:71].sum() == whole.pair_collisions.sum()


@pytest.mark.parametrize("block", [1, 7])
def test_ccd_gives_the_same_bytes_whatever_the_block_size(block):
    # under gravity and with restitution < 1, where restarting the loop at block ends used to drift
    scene = collisim.load_scene("particles_250").replace(method="ccd", seconds=1.5)
    scene = scene.replace(world=scene.world.copy(gravity=(0.0, -9.8), restitution=0.9))
    whole = collisim.simulate(scene)
    streamed = concatenate(list(stream(scene, block=block)))
    for name in ("positions", "velocities", "wall_collisions", "pair_collisions"):
        np.testing.assert_array_equal(getattr(streamed, name), getattr(whole, name), err_msg=name)
    for name in ("time", "kind", "i", "j", "impulse", "point"):
        np.testing.assert_array_equal(getattr(streamed.events, name), getattr(whole.events, name), err_msg=name)


def test_ccd_same_input_same_bytes():
    scene = collisim.load_scene("particles_250").replace(method="ccd", seconds=2.0)
    digests = {hashlib.sha256(collisim.simulate(scene).positions.tobytes()).hexdigest() for _ in range(2)}
    assert len(digests) == 1


def test_ccd_momentum_is_conserved_without_walls():
    rng = np.random.default_rng(5)
    n = 60
    positions = np.column_stack([np.arange(n) % 10 * 3.0 + 500, np.arange(n) // 10 * 3.0 + 500])
    world = collisim.World(positions=positions, velocities=rng.normal(0, 2, (n, 2)),
                           radii=rng.uniform(0.5, 1.2, n), box=(0, 0, 1000, 1000))
    traj = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=5.0, method="ccd"))
    assert traj.pair_collisions.sum() > 20 and traj.wall_collisions.sum() == 0
    p = traj.momentum()
    scale = np.sum(world.masses * np.hypot(*world.velocities.T))
    assert np.abs(p - p[0]).max() <= 1e-12 * scale


def test_ccd_needs_uniform_gravity():
    world = collisim.World(positions=[[2, 2], [5, 5]], accelerations=[[0, -1], [0, -2]])
    with pytest.raises(ValueError, match="uniform gravity"):
        collisim.simulate(collisim.Scene(world=world, method="ccd"))


def test_frames_over_the_event_budget_are_flagged_counted_and_said_once(tmp_path, monkeypatch):
    from collisim import engine
    from collisim.engine.ccd import CCDStepper
    # a small budget, so the gas's busiest frames go over it
    monkeypatch.setitem(engine.METHODS, "ccd", lambda s: CCDStepper(s.world, s.fps, s.frames, max_events_per_frame=3))
    scene = collisim.load_scene("particles_250").replace(method="ccd", seconds=0.5)
    with pytest.warns(UserWarning) as caught:
        traj = collisim.simulate(scene)
    flagged = int(traj.approximate.sum())
    assert 0 < flagged <= traj.frames and not traj.approximate[0]
    messages = [str(w.message) for w in caught]
    assert len(messages) == 1 and messages[0].startswith(f"{flagged} of 30 frames of particles_250 are approximate")
    assert "more than 3 events in a frame" in messages[0]
    shown = int(traj.approximate[:30].sum())   # a 30-frame video shows samples 0 .. 29
    with pytest.warns(UserWarning, match=f"{shown} of 30 frames of the scene are approximate") as rendered:
        collisim.render(scene, tmp_path / "gas.mp4", (160, 90))
    assert len(rendered) == 1
    with pytest.warns(UserWarning, match=f"{shown} of 30 frames of the scene are approximate") as still:
        collisim.render(scene, tmp_path / "gas.png", (160, 90), png_frame=29)   # a still says so too
    assert len(still) == 1


def test_the_event_budget_grows_with_the_number_of_bodies():
    from collisim.engine.ccd import CCDStepper
    small = collisim.World([[1, 1]])
    assert CCDStepper(small, 60, 1).max_events == 100_000
    positions, _, radii = lattice_gas(20_000, box=(0, 0, 400, 400), speed=1.0, seed=1)
    assert CCDStepper(collisim.World(positions, radii=radii, box=(0, 0, 400, 400)), 60, 1).max_events == 64 * 20_000
