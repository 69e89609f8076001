"""The benchmarks' speed baselines: plain pymunk as a user would run it, and the minimal compiled
reference step. Both must be the physics they claim to be, or the ratios against them mean nothing."""
import csv

import numpy as np
import pymunk
import pytest

import collisim
from collisim.analysis.bench import broadphase
from collisim.analysis.bench.reference_step import MinimalStep
from collisim.analysis.bench.workloads import packing_fraction, shuffled_gas
from collisim.analysis.reference import PlainPymunk, simulate_plain_pymunk, simulate_pymunk, time_plain_pymunk
from collisim.analysis.reference.pymunk_mirror import Mirror
from collisim.gas import lattice_gas
from collisim.core.kinds import PAIR, WALL


def head_on(gravity=(0.0, 0.0)):
    """Two circles of different sizes (so different masses) closing at 6 units/s, 6 apart."""
    return collisim.World([[2.0, 5.0], [8.0, 5.0]], [[3.0, 0.0], [-3.0, 0.0]], [0.6, 0.8],
                          box=(0.0, 0.0, 10.0, 10.0), gravity=gravity)


# --- plain pymunk ----------------------------------------------------------------------------

def test_plain_pymunk_builds_the_same_world_with_pymunk_defaults():
    world = collisim.World([[2.0, 5.0], [8.0, 5.0], [5.0, 2.0]], [[3.0, 0.0], [-3.0, 1.0], [0.0, 0.5]],
                           [0.6, 0.8, 0.5], box=(0.0, 0.0, 10.0, 8.0), gravity=(0.0, -9.8), restitution=0.9,
                           segments=[[1.0, 1.0, 4.0, 1.5]])
    plain = PlainPymunk(world)
    space, defaults = plain.space, pymunk.Space()
    assert tuple(space.gravity) == (0.0, -9.8)
    assert (space.collision_slop, space.collision_bias, space.iterations, space.damping) == \
        (defaults.collision_slop, defaults.collision_bias, defaults.iterations, defaults.damping)
    dynamic = [body for body in space.bodies if body.body_type == pymunk.Body.DYNAMIC]
    assert dynamic == plain.bodies and len(dynamic) == 3
    for i, body in enumerate(dynamic):
        assert body.mass == pytest.approx(world.masses[i], rel=1e-15)
        assert body.moment == pytest.approx(world.inertias[i], rel=1e-15)    # ½·m·r², not infinite
        assert tuple(body.position) == tuple(world.positions[i])
        assert tuple(body.velocity) == tuple(world.velocities[i])
        (circle,) = body.shapes
        assert isinstance(circle, pymunk.Circle) and circle.radius == world.radii[i]
        assert (circle.elasticity ** 2, circle.friction) == (pytest.approx(0.9), 0.0)   # pairs meet with e
    statics = [shape for shape in space.shapes if shape.body.body_type == pymunk.Body.STATIC]
    assert len(statics) == 4 + 1 and all(isinstance(s, pymunk.Segment) and s.radius == 0 for s in statics)
    assert all((s.elasticity ** 2, s.friction) == (pytest.approx(0.9), 0.0) for s in statics)
    ends = {(tuple(s.a), tuple(s.b)) for s in statics}
    assert ends == {((0, 0), (0, 8)), ((10, 0), (10, 8)), ((0, 0), (10, 0)), ((0, 8), (10, 8)), ((1, 1), (4, 1.5))}


def test_an_abandoned_plain_pymunk_space_steps_as_before_and_is_let_go_without_freeing():
    """The benchmark abandons pymunk's spaces of large worlds (freeing them is quadratic in
    their size): stepping is unchanged, and dropping the space runs no destructor, so a body
    still held stays in the (never freed) space, where a freed space would have removed it."""
    import gc

    from pymunk._chipmunk_cffi import ffi, lib

    scene = broadphase.moving_gas(400, 0.3, 2)
    kept, abandoned = PlainPymunk(scene.world), PlainPymunk(scene.world)
    abandoned.abandon()
    for plain in (kept, abandoned):
        plain.time_steps(scene.fps, 30)
    np.testing.assert_array_equal(np.asarray(abandoned.state()[0]), np.asarray(kept.state()[0]))
    held = {"kept": kept.bodies[0], "abandoned": abandoned.bodies[0]}
    del kept, abandoned, plain
    gc.collect()
    assert lib.cpBodyGetSpace(held["kept"]._body) == ffi.NULL         # freed: its bodies were removed
    assert lib.cpBodyGetSpace(held["abandoned"]._body) != ffi.NULL    # abandoned: nothing ran


def test_plain_pymunk_installs_no_collision_handler():
    world = head_on()
    plain = PlainPymunk(world)
    assert plain.installed_handlers() == 0 and plain.space._handlers == {}
    assert len(Mirror(world).space._handlers) == 3      # the check would see the mirror's callbacks
    simulate_plain_pymunk(collisim.Scene(world=world, fps=60, seconds=0.5))   # recording adds none either
    assert PlainPymunk(world).space._handlers == {}


def test_free_flight_under_gravity_agrees_with_the_mirror_bit_for_bit():
    """Both are Chipmunk's semi-implicit Euler in doubles with the same dt: before any contact
    the two Spaces do exactly the same arithmetic (the moments differ, but nothing turns)."""
    world = collisim.World([[3.0, 8.0], [7.0, 6.0]], [[1.0, 2.0], [-1.0, 0.0]], 0.5, box=(0.0, 0.0, 10.0, 10.0),
                           gravity=(0.0, -9.8))
    scene = collisim.Scene(world=world, fps=60, seconds=0.5)        # both still in the air at 0.5 s
    plain, mirror = simulate_plain_pymunk(scene), simulate_pymunk(scene)
    assert plain.collisions.sum() == mirror.collisions.sum() == 0
    assert np.array_equal(plain.positions, mirror.positions)
    assert np.array_equal(plain.velocities, mirror.velocities)


def test_one_collision_agrees_with_the_mirror():
    """An isolated elastic contact is solved exactly by Chipmunk whatever its settings: the
    velocities after it agree to round-off (1e-12 of the speeds). The positions do not: the
    mirror removes the overlap found at detection in the next step, plain pymunk leaves an
    overlap under its 0.1 slop, so they differ by at most that overlap, which is at most the
    distance the pair closes in one step (6 units/s × 1/60 s = 0.1)."""
    scene = collisim.Scene(world=head_on(), fps=60, seconds=1.2)     # one pair contact, no wall yet
    plain, mirror = simulate_plain_pymunk(scene), simulate_pymunk(scene)
    assert plain.pair_collisions.sum() == mirror.pair_collisions.sum() == 1
    assert plain.wall_collisions.sum() == mirror.wall_collisions.sum() == 0
    assert np.allclose(plain.velocities[-1], mirror.velocities[-1], rtol=0, atol=1e-12 * 3.0)
    closing_per_step = 6.0 / 60
    assert np.abs(plain.positions - mirror.positions).max() <= closing_per_step
    # the recorded events: the same impulse at the same step, between the same pair
    (p,), (m,) = (np.flatnonzero(t.events.kind == PAIR) for t in (plain, mirror))
    assert plain.events.time[p] == mirror.events.time[m]
    assert plain.events.impulse[p] == pytest.approx(mirror.events.impulse[m], rel=1e-12)
    assert (plain.events.i[p], plain.events.j[p]) == (0, 1)


def test_walls_are_thin_and_a_fast_particle_escapes_through_one():
    """What a user's thin static segment does: a centre that crosses the wall's line within one
    step is pushed out (the segment is two-sided) and the particle is lost; with 8 substeps it
    bounces. The mirror's thick walls keep it in either way."""
    world = collisim.World([[5.0, 5.0]], [[200.0, 0.0]], 0.5, box=(0.0, 0.0, 10.0, 10.0))
    scene = collisim.Scene(world=world, fps=60, seconds=0.05)          # 3.3 units a frame: 2 radii to cross
    assert simulate_plain_pymunk(scene).positions[-1, 0, 0] > 10.0
    assert simulate_pymunk(scene).positions[-1, 0, 0] < 10.0
    bounced = simulate_plain_pymunk(scene, substeps=8)
    assert bounced.positions[-1, 0, 0] < 10.0 and bounced.wall_collisions.sum() == 1
    assert bounced.events.kind[0] == WALL and bounced.events.j[0] == 1     # the right wall


def test_timing_a_plain_run_steps_the_space_only():
    scene = collisim.Scene(world=head_on(), fps=60, seconds=0.5)
    assert time_plain_pymunk(scene, substeps=2) > 0
    plain = PlainPymunk(scene.world)
    plain.time_steps(60, 30)
    recorded = PlainPymunk(scene.world).record(60, 30)
    assert np.array_equal(plain.state()[0], recorded.positions[-1])   # recording changes nothing
    with pytest.raises(ValueError, match="substeps"):
        time_plain_pymunk(scene, substeps=0)


# --- the minimal step --------------------------------------------------------------------------

def minimal(world, margin=0.0):
    """The minimal step on a world's gas at 60 fps, its box widened by `margin` on every side."""
    box = np.asarray(world.box) + np.array([-margin, -margin, margin, margin])
    return MinimalStep(world.positions, world.velocities, world.radii, world.masses, box, dt=1 / 60)


def brute_force_touching(positions, radii) -> int:
    i, j = np.triu_indices(len(positions), 1)
    return int(np.count_nonzero(np.hypot(*(positions[i] - positions[j]).T) < radii[i] + radii[j]))


def test_minimal_step_head_on_equal_masses_swap_velocities():
    step = MinimalStep([[4.0, 5.0], [6.0, 5.0]], [[1.0, 0.0], [-1.0, 0.0]], 0.5, 1.0, (0.0, 0.0, 10.0, 10.0),
                       dt=0.1)
    step.run(8)       # they touch after 5 steps and part
    assert np.allclose(step.velocities, [[-1.0, 0.0], [1.0, 0.0]], rtol=0, atol=1e-15)


def test_minimal_step_finds_every_touching_pair_brute_force_finds():
    """At packing 0.5 the half stencil must find each touching pair once, across cell edges and
    in the box's last row and column: its count after a step (positions change only in the move,
    so its pairs are those of the final positions) against all pairs checked."""
    world = shuffled_gas(500, 0.5, seed=4)
    step = minimal(world)
    found = []
    for _ in range(6):
        step.run(10)
        found.append(step.touching)
        assert step.touching == brute_force_touching(step.positions, world.radii)
    assert min(found) > 5


def test_minimal_step_keeps_energy_and_momentum_and_the_bodies_in_the_box():
    """An elastic gas at packing 0.3, 120 steps: each impulse keeps kinetic energy and momentum
    in exact arithmetic and a wall reflection keeps the speed, so energy changes by round-off
    alone (a wrong mass factor would change it by 1e-2 or more); in a box widened so that no
    body reaches a wall, momentum too."""
    world = shuffled_gas(300, 0.3, seed=5)
    for margin in (0.0, 40.0):
        step = minimal(world, margin)
        energy, momentum = step.kinetic_energy(), step.momentum()
        scale = float(np.sum(world.masses * np.hypot(*world.velocities.T)))
        step.run(120)
        assert abs(step.kinetic_energy() - energy) <= 1e-12 * energy
        if margin:
            assert np.abs(step.momentum() - momentum).max() <= 1e-12 * scale
        low, high = np.asarray(step.box[:2]), np.asarray(step.box[2:])
        r = world.radii[:, None]
        assert ((step.positions >= low + r) & (step.positions <= high - r)).all()
        assert np.array_equal(np.sort(step.ids), np.arange(world.n))      # every body still there once
    changed = np.abs(np.hypot(*step.velocities.T) - np.hypot(*world.velocities.T)) > 1e-6
    assert changed.mean() > 0.5       # they did collide: only pair impulses change a speed


def test_the_shuffled_gas_is_the_laid_out_gas_in_another_order():
    """The same bodies (position, velocity, radius) as the gas laid out row by row, in an order
    unrelated to where they are; at the packing asked, none overlapping."""
    laid_out, mixed = shuffled_gas(400, 0.5, seed=2, shuffle=False), shuffled_gas(400, 0.5, seed=2)

    def rows(world):
        table = np.column_stack([world.positions, world.velocities, world.radii])
        return table[np.lexsort(table.T[::-1])]

    assert np.array_equal(rows(laid_out), rows(mixed))
    assert not np.array_equal(laid_out.positions, mixed.positions)
    rank = np.argsort(np.argsort(mixed.positions[:, 1]))      # row order: index against height
    assert abs(np.corrcoef(rank, np.arange(400))[0, 1]) < 0.15
    assert packing_fraction(mixed) == pytest.approx(0.5)
    assert brute_force_touching(mixed.positions, mixed.radii) == 0


# --- matched materials -------------------------------------------------------------------------

def two_boxes_on_the_floor():
    from collisim.shapes import box
    return collisim.World([[3.0, 0.5], [3.2, 1.5]], polygons=[box(1.0, 1.0)] * 2, angles=0.0,
                          box=(0.0, 0.0, 8.0, 6.0), gravity=(0.0, -10.0), restitution=0.3, friction=0.4)


def test_plain_pymunk_pairs_meet_with_the_worlds_e_and_mu():
    """Chipmunk multiplies the shapes' elasticity and friction: every touching pair, box on box
    and box on the floor, must meet with the World's e = 0.3 and μ = 0.4 (not 0.09 and 0.16)."""
    plain = PlainPymunk(two_boxes_on_the_floor())
    for _ in range(5):
        plain.space.step(1 / 60)
    met = []

    def meet(arbiter):
        a, b = arbiter.shapes
        met.append((arbiter.restitution, arbiter.friction, a.body.body_type == b.body.body_type))

    for body in plain.bodies:
        body.each_arbiter(meet)
    assert {pair for *_, pair in met} == {True, False}        # a pair and a body on a wall
    assert all(e == pytest.approx(0.3) and mu == pytest.approx(0.4) for e, mu, _ in met)


def test_box2d_pairs_meet_with_the_worlds_e_and_mu():
    """Box2D mixes friction as √(μa·μb) and restitution as max: its touching contacts, box on box
    and box on the floor, must carry the World's e and μ (float32)."""
    pytest.importorskip("Box2D")
    from collisim.analysis.reference.box2d_world import Box2DWorld
    reference = Box2DWorld(two_boxes_on_the_floor(), 60.0)
    reference.step(5)
    touching = [contact for contact in reference.b2.contacts if contact.touching]
    assert len(touching) == 2
    assert all(c.restitution == pytest.approx(0.3, rel=1e-6) and c.friction == pytest.approx(0.4, rel=1e-6)
               for c in touching)


# --- the benches' new columns -----------------------------------------------------------------

def test_broadphase_bench_reports_plain_pymunk_and_the_minimal_step(tmp_path):
    figures = broadphase.run(tmp_path, sizes=(50, 200), packings=(0.3,), repeats=1, progress=False)
    with open(figures["csv"], newline="") as file:
        rows = list(csv.DictReader(file))
    assert tuple(rows[0]) == broadphase.COLUMNS
    assert {"pymunk_step", "minimal_step", "discrete_step", "simulate"} <= {row["method"] for row in rows}
    for n in (50, 200):
        time_of = {row["method"]: float(row["seconds_per_frame"]) for row in rows if row["n"] == str(n)}
        (step,) = (row for row in rows if row["n"] == str(n) and row["method"] == "discrete_step")
        assert float(step["step_over_minimal"]) == pytest.approx(time_of["discrete_step"] / time_of["minimal_step"])
        assert figures["ratios"][(0.3, n)]["simulate / pymunk"] == pytest.approx(
            time_of["simulate"] / time_of["pymunk_step"])


def test_broadphase_pymunk_baseline_is_plain_pymunk(monkeypatch):
    """The timed Space is plain pymunk's: the mirror is never built for the speed baseline."""
    built = []
    monkeypatch.setattr("collisim.analysis.reference.pymunk_mirror.Mirror.__init__",
                        lambda self, *a, **k: built.append(self))
    scene = broadphase.moving_gas(50, 0.1, 0)
    assert broadphase.time_pymunk(scene, 1) > 0 and built == []
