"""ccd's cell grid with mixed sizes: a few large bodies kept out of the cell lists give the same
events as cells sized by the largest body (broadphase/cells.py)."""
import numpy as np

from collisim.core.geometry.segment import segment_contact
from collisim.broadphase.cells import choose_apart, make_grid
from collisim.engine.ccd.events import simulate_events
from collisim.gas import lattice_gas


RAMPS = np.array([[2.0, 25.0, 15.0, 22.0], [38.0, 20.0, 25.0, 27.0]])


def mixed_gas():
    """400 small particles, the ones under two large disks or on the ramps removed, the large
    disks added."""
    box = (0.0, 0.0, 40.0, 30.0)
    positions, velocities, radii = lattice_gas(400, box=box, speed=4.0, seed=2)
    large = np.array([[12.0, 15.0], [28.0, 12.0]])
    large_radii = np.array([3.0, 2.2])
    clear = np.ones(len(positions), bool)
    for centre, radius in zip(large, large_radii):
        clear &= np.hypot(*(positions - centre).T) > radius + radii + 1e-3
    for ramp in RAMPS:
        clear &= np.array([segment_contact(x, y, ramp)[2] for x, y in positions]) > radii + 1e-3
    positions = np.vstack([positions[clear][:150], large, positions[clear][150:]])
    velocities = np.vstack([velocities[clear][:150], [[2.0, 1.0], [-1.5, 0.5]], velocities[clear][150:]])
    radii = np.concatenate([radii[clear][:150], large_radii, radii[clear][150:]])
    return positions, velocities, radii, box


def test_a_few_large_bodies_are_kept_apart_and_uniform_gases_are_not():
    positions, _, radii, box = mixed_gas()
    assert choose_apart(np.array(box), radii).tolist() == [150, 151]
    assert choose_apart(np.array(box), np.full(400, 0.3)).size == 0
    assert choose_apart(np.array(box), np.linspace(0.2, 0.45, 400)).size == 0
    apart, together = make_grid(np.array(box), radii, np.zeros((0, 4))), make_grid(np.array(box), radii,
                                                                                    np.zeros((0, 4)), False)
    assert apart.nx * apart.ny > 10 * together.nx * together.ny
    assert apart.reach[150] >= 2 and apart.reach[151] >= 2 and np.all(np.delete(apart.reach, [150, 151]) == 1)


def run(separate_large, gravity=(0.0, 0.0), restitution=1.0, segments=None, frames=60):
    positions, velocities, radii, box = mixed_gas()
    return simulate_events(positions, velocities, gravity, radii, radii ** 2, box, restitution, segments, 1 / 30,
                           frames, separate_large=separate_large)


def assert_same_run(a, b):
    assert len(a.time) > 500 and not a.budget_exceeded.any()
    np.testing.assert_array_equal(a.kind, b.kind)
    np.testing.assert_array_equal(a.i, b.i)
    np.testing.assert_array_equal(a.j, b.j)
    # Other cells mean other reference times and so other roundings, which a gas amplifies
    # (each collision multiplies a difference by a few): close early, same events throughout.
    np.testing.assert_allclose(a.positions[:10], b.positions[:10], rtol=0, atol=1e-10)
    np.testing.assert_allclose(a.time, b.time, rtol=0, atol=1e-4)


def test_keeping_large_bodies_apart_gives_the_same_events_as_cells_sized_by_the_largest():
    apart, together = run(True), run(False)
    assert_same_run(apart, together)
    large_pairs = (apart.kind == 1) & ((apart.i == 150) | (apart.i == 151) | (apart.j == 150) | (apart.j == 151))
    assert large_pairs.sum() > 30     # the large disks do collide with the small ones


def test_the_same_under_gravity_with_segments():
    # 1.2 s: by 1.8 s the amplified roundings reorder two collisions 1e-5 s apart
    apart = run(True, gravity=(0.0, -5.0), restitution=0.95, segments=RAMPS, frames=36)
    together = run(False, gravity=(0.0, -5.0), restitution=0.95, segments=RAMPS, frames=36)
    assert_same_run(apart, together)
    assert (apart.kind == 2).sum() > 10
