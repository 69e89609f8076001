"""The teacher's ready-made items (render/teach.py) against closed forms: an elastic head-on
collision of two masses keeps momentum and kinetic energy and ends at the textbook
velocities; arrows are as long as |v| (or m|v|) times their scale; the centre of mass moves at
P/M; all of them draw, from one line each, in a rendered frame."""
import numpy as np
import pytest

import collisim
from collisim.core.kinds import PAIR, WALL
from collisim.render import teach
from collisim.render.explain import Explainer, resolve
from collisim.render.player import FrameState
from collisim.render.timeline import Timeline

M1, M2, U1, U2 = 1.0, 3.0, 2.0, -1.0


@pytest.fixture(scope="module")
def head_on():
    world = collisim.World(positions=[[2.0, 3.0], [6.0, 3.0]], velocities=[[U1, 0.0], [U2, 0.0]], radii=0.5,
                           masses=[M1, M2], box=(0.0, 0.0, 12.0, 6.0), restitution=1.0)
    return world, collisim.simulate(collisim.Scene(world=world, fps=60, seconds=1.5, method="discrete"))


def states(trajectory):
    memory = {}
    for f in range(len(trajectory.times)):
        past = trajectory.events.take(trajectory.events.time <= trajectory.times[f] + 1e-12)
        yield FrameState(float(trajectory.times[f]), f, trajectory.positions[f], trajectory.velocities[f],
                         trajectory.angles[f], 0, 0, 0, 0, past, memory=memory)


def test_the_readout_keeps_momentum_and_energy_across_an_elastic_collision(head_on):
    world, trajectory = head_on
    assert np.count_nonzero(trajectory.events.kind == PAIR) == 1 and not (trajectory.events.kind == WALL).any()
    momentum, energy = np.array([M1 * U1 + M2 * U2, 0.0]), 0.5 * (M1 * U1 ** 2 + M2 * U2 ** 2)
    for state in states(trajectory):
        found = teach.readout(world, state)
        p, e = found["now"]
        v = state.velocities
        np.testing.assert_allclose(p, M1 * v[0] + M2 * v[1], atol=1e-12)       # sum m v of the sample
        np.testing.assert_allclose(p, momentum, atol=1e-9)
        assert e == pytest.approx(energy, rel=1e-9)
    (before_p, before_e), (after_p, after_e) = found["before"], found["after"]
    np.testing.assert_allclose([before_p, after_p], [momentum, momentum], atol=1e-9)
    assert before_e == pytest.approx(after_e, rel=1e-9) == energy
    # the textbook's elastic velocities: v1' = ((m1 - m2) u1 + 2 m2 u2) / (m1 + m2), and v2'
    v1 = ((M1 - M2) * U1 + 2 * M2 * U2) / (M1 + M2)
    v2 = ((M2 - M1) * U2 + 2 * M1 * U1) / (M1 + M2)
    np.testing.assert_allclose(trajectory.velocities[-1][:, 0], [v1, v2], atol=1e-9)
    assert "$\\to$" in teach.momentum_energy(world).text(state)


def test_arrows_are_as_long_as_speed_and_momentum_times_their_scale(head_on):
    world, trajectory = head_on
    velocity, momentum = teach.velocity_arrows(world, seconds=0.5), teach.momentum_arrows(world, per_unit=0.2)
    for state in list(states(trajectory))[::20]:
        speeds = np.hypot(*state.velocities.T)
        for k in range(2):
            for arrow, length in ((velocity[k], 0.5 * speeds[k]), (momentum[k], 0.2 * world.masses[k] * speeds[k])):
                tail, head = resolve(arrow.tail, state), resolve(arrow.head, state)
                np.testing.assert_allclose(tail, state.positions[k])
                assert np.hypot(*(head - tail)) == pytest.approx(length, rel=1e-12)


def test_the_centre_of_mass_moves_at_total_momentum_over_total_mass(head_on):
    world, trajectory = head_on
    note = teach.centre_of_mass(world)
    start = np.array([M1 * 2.0 + M2 * 6.0, (M1 + M2) * 3.0]) / (M1 + M2)
    drift = np.array([M1 * U1 + M2 * U2, 0.0]) / (M1 + M2)
    for state in states(trajectory):
        np.testing.assert_allclose(resolve(note.at, state), start + state.time * drift, atol=1e-9)


def test_each_item_is_one_line_of_a_scene_and_draws_where_the_layout_puts_it(head_on):
    world, _ = head_on
    explainer = Explainer([*teach.velocity_arrows(world), *teach.momentum_arrows(world), teach.centre_of_mass(world),
                           teach.momentum_energy(world), teach.data_table(world)], side=0.35, fade=0.0)
    scene = collisim.Scene(world=world, fps=60, seconds=1.5, render=collisim.RenderSettings(explainer=explainer))
    job = collisim.pipeline.plan(scene, quality="l")
    timeline = Timeline(job.chapters, job.size, job.fps)
    canvas = np.empty((job.size[1], job.size[0], 3), np.uint8)
    for frame in range(0, job.frames, 3):
        timeline.draw(canvas, frame)
    kinds = [label.kind for _, label in timeline.placed()]
    assert kinds.count("arrow") == 4 and kinds.count("note") == 1 and kinds.count("table") == 3
    assert all(label.fits for _, label in timeline.placed())
    rows = teach.table_rows(world, timeline._players[0].state)
    assert rows[1][:2] == ["1", f"{M1:.2f}"] and rows[2][:2] == ["2", f"{M2:.2f}"]
