"""A large gas stepped with its bodies kept in cell order (engine/cell_order.py): the trajectory
and the events speak of the world's bodies, whatever the step's own numbering; the bytes do not
depend on the blocks or the broad phase; a gas too sparse for any body to meet two others in a
step runs exactly as without the renumbering."""
import numpy as np
import pytest

import collisim
from collisim.analysis.bench.workloads import shuffled_gas
from collisim.core.kinds import PAIR
from collisim.engine import cell_order
from collisim.engine.simulate import concatenate


@pytest.fixture
def small_orders(monkeypatch):
    """Worlds of a few hundred bodies renumbered as a large gas is (the threshold is a matter of
    cache sizes, not of what the renumbering does)."""
    monkeypatch.setattr(cell_order, "ORDER_MIN", 100)


def run(world, broadphase="grid", seconds=0.5, block=None):
    scene = collisim.Scene(world=world, fps=60, seconds=seconds, broadphase=broadphase)
    return collisim.simulate(scene) if block is None else concatenate(list(collisim.stream(scene, block=block)))


def assert_same(a, b, candidates=True):
    """The same bytes, but for each pair impact's point, which may come from the other body's side
    of the contact (the lower number's, in the step's numbering): the same point to rounding."""
    for name in ("positions", "velocities", "angles", "wall_collisions", "pair_collisions") + ("candidates",) * candidates:
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    for name in ("time", "kind", "i", "j", "impulse"):
        np.testing.assert_array_equal(getattr(a.events, name), getattr(b.events, name), err_msg=name)
    np.testing.assert_allclose(a.events.point, b.events.point, rtol=1e-14, atol=0)


@pytest.mark.parametrize("friction", [0.0, 0.5])
def test_a_sparse_gas_runs_exactly_as_without_renumbering(monkeypatch, friction):
    # at packing 0.05 no body meets two others in one step, so the order of the contacts does not
    # matter and every byte must agree: the state and events are put back in the world's numbers
    # (with friction the bodies spin, and their angles are recorded every frame)
    gas = shuffled_gas(400, 0.05, 3)
    world = collisim.World(positions=gas.positions, velocities=gas.velocities, radii=gas.radii, masses=gas.masses,
                           box=gas.box, friction=friction)
    plain = run(world, seconds=1.0)
    monkeypatch.setattr(cell_order, "ORDER_MIN", 100)
    renumbered = run(world, seconds=1.0)
    assert len(plain.events) > 50 and (friction == 0) == (plain.angles.strides[0] == 0)
    assert_same(renumbered, plain)
    np.testing.assert_array_equal(renumbered.angular_velocities, plain.angular_velocities)


def test_a_dense_gas_has_the_same_bytes_whatever_the_blocks_and_the_broad_phase(small_orders):
    world = shuffled_gas(1500, 0.4, 4)
    whole = run(world)
    assert_same(run(world, block=7), whole)                       # renumbered in mid-block
    # sweep and prune keeps its order from step to step; its candidates are its own (README)
    assert_same(run(world, broadphase="sweep_prune"), whole, candidates=False)
    energy = 0.5 * (world.masses * np.sum(whole.velocities ** 2, axis=2)).sum(axis=1)
    assert np.ptp(energy) < 1e-12 * energy[0]                     # elastic: nothing lost in the renumbering
    pair = whole.events.kind == PAIR
    assert pair.sum() > 1000 and np.all(whole.events.i[pair] < whole.events.j[pair])


def test_the_warm_start_memory_follows_the_bodies_to_their_new_numbers():
    # rows of pairs (i < j) and of bodies on walls, keyed as warmstart.row_key keys them; after the
    # renumbering each impulse must sit under the key its contact has in the new numbers
    rng = np.random.default_rng(5)
    n, statics = 50, cell_order.MEMORY_STATICS
    i = rng.integers(0, n, 40)
    other = np.where(rng.random(40) < 0.7, rng.integers(0, n, 40), n + rng.integers(0, statics, 40))
    keep = (other >= n) | (i != other)
    i, other = i[keep], other[keep]
    body = other < n
    i, other = np.where(body, np.minimum(i, other), i), np.where(body, np.maximum(i, other), other)
    feature = rng.integers(0, 2, len(i))
    keys = 2 * (i * (n + statics) + other) + feature
    keys, first = np.unique(keys, return_index=True)
    impulses = rng.random(len(keys))
    memory = cell_order.Memory(keys, impulses, -impulses)
    new_of_old = rng.permutation(n)
    moved = cell_order.renumbered_memory(memory, new_of_old, statics)
    i, other, feature = i[first], other[first], feature[first]
    new_i = new_of_old[i]
    new_other = np.where(other < n, new_of_old[np.minimum(other, n - 1)], other)
    low, high = np.where(other < n, np.minimum(new_i, new_other), new_i), np.where(other < n, np.maximum(new_i, new_other), new_other)
    expected = dict(zip(2 * (low * (n + statics) + high) + feature, impulses))
    assert np.all(np.diff(moved.keys) > 0)
    assert dict(zip(moved.keys, moved.impulses)) == expected
    np.testing.assert_array_equal(moved.frictions, -moved.impulses)
