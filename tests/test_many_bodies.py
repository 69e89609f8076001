"""Many bodies through the full discrete pipeline: every broad phase gives the same bytes."""
import hashlib

import numpy as np
import pytest

import collisim
from collisim.broadphase import NAMES


def digest(traj) -> str:
    h = hashlib.sha256()
    for array in (traj.positions, traj.velocities, traj.wall_collisions, traj.pair_collisions):
        h.update(np.ascontiguousarray(array).tobytes())
    return h.hexdigest()


@pytest.fixture(scope="module")
def gas_scene():
    return collisim.load_scene("particles_250").replace(seconds=10.0)   # 600 frames


@pytest.fixture(scope="module")
def reference(gas_scene):
    return collisim.simulate(gas_scene.replace(broadphase="brute"))


@pytest.mark.parametrize("method", [m for m in NAMES if m != "brute"])
def test_every_broad_phase_gives_identical_trajectory_bytes(gas_scene, reference, method):
    traj = collisim.simulate(gas_scene.replace(broadphase=method))
    assert traj.frames == 600
    assert digest(traj) == digest(reference)


def test_the_gas_collides_conserves_energy_and_stays_in_the_box(gas_scene, reference):
    assert reference.pair_collisions.sum() > 500 and reference.wall_collisions.sum() > 100
    ke = reference.kinetic_energy()
    # elastic impulses and overlap removal change no kinetic energy
    np.testing.assert_allclose(ke, np.full_like(ke, ke[0]), rtol=1e-12)
    xmin, ymin, xmax, ymax = gas_scene.world.box
    r = reference.radii[None, :]
    p = reference.positions
    assert np.all(p[..., 0] - r >= xmin - 1e-12) and np.all(p[..., 0] + r <= xmax + 1e-12)
    assert np.all(p[..., 1] - r >= ymin - 1e-12) and np.all(p[..., 1] + r <= ymax + 1e-12)


def test_same_input_same_bytes(gas_scene):
    short = gas_scene.replace(seconds=1.0, broadphase="grid")
    assert digest(collisim.simulate(short)) == digest(collisim.simulate(short))


def test_one_particle_runs_no_pair_phase():
    world = collisim.World(positions=[[5, 5]], velocities=[[1, 2]])
    traj = collisim.simulate(collisim.Scene(world=world, seconds=0.5))
    assert traj.profile.get("broad", 0.0) == 0.0 and traj.broadphase == ""
    assert {"integrate", "statics"} <= set(traj.profile)


def test_profile_records_every_phase_of_a_many_body_step(gas_scene):
    traj = collisim.simulate(gas_scene.replace(seconds=0.25))
    assert {"integrate", "broad", "narrow", "response", "statics", "settle"} <= set(traj.profile)
    assert all(seconds >= 0 for seconds in traj.profile.values())
    # every phase that does work in a gas is timed (a lap left out gives its time to the next)
    assert all(traj.profile[phase] > 0 for phase in ("integrate", "broad", "narrow", "response", "statics"))


def test_render_cli_with_broadphase_substeps_restitution_and_profile(cli, tmp_path):
    from conftest import decode_video
    out = tmp_path / "gas.mp4"
    result = cli("render", "particles_250", "--seconds", "0.5", "--size", "320x180", "--broadphase", "grid",
                 "--substeps", "2", "--restitution", "0.9", "--profile", "--no-progress", "--out", out)
    assert result.returncode == 0, result.stderr
    assert decode_video(out)[:3] == (30, 320, 180)
    for phase in ("integrate", "broad", "narrow", "response", "statics", "draw", "encode"):
        assert phase in result.stdout
    bad = cli("render", "particles_250", "--broadphase", "octree", "--out", tmp_path / "x.mp4")
    assert bad.returncode == 2 and "'octree'" in bad.stderr and "sweep_prune" in bad.stderr
    assert len(bad.stderr.strip().splitlines()) == 1


def test_bench_broadphase_writes_csv_and_chart_with_reference_lines(cli, tmp_path):
    import csv
    result = cli("bench", "broadphase", "--sizes", "50", "400", "--repeats", "1", "--packing", "0.1", "--no-progress",
                 "--out", tmp_path)
    assert result.returncode == 0, result.stderr
    rows = list(csv.DictReader(open(tmp_path / "broadphase.csv")))
    methods = {row["method"] for row in rows}
    assert set(NAMES) | {"scipy_ckdtree", "pymunk_step", "discrete_step"} <= methods
    for n in ("50", "400"):   # every method finds every touching pair
        true_pairs = {row["true_pairs"] for row in rows if row["n"] == n and row["method"] in NAMES}
        assert len(true_pairs) == 1
    assert (tmp_path / "broadphase.png").stat().st_size > 10_000
    assert "x cKDTree" in result.stdout
