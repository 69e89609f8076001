"""The accuracy benchmark: its workloads are what they claim, and one short run writes a CSV and a
chart whose numbers behave as the physics says they must."""
import csv

import numpy as np
import pytest

import collisim
from collisim.analysis import metrics
from collisim.analysis.bench import accuracy
from collisim.analysis.reference import simulate_plain_pymunk
from collisim.analysis.bench.workloads import WORKLOADS, mean_radii_per_frame, packing_fraction


def smallest_gap(world) -> float:
    """The smallest distance between two circles' surfaces (negative: they overlap)."""
    apart = np.linalg.norm(world.positions[:, None] - world.positions[None], axis=2)
    reach = world.radii[:, None] + world.radii[None]
    np.fill_diagonal(apart, np.inf)
    return float((apart - reach).min())


@pytest.mark.parametrize("name", list(WORKLOADS))
def test_workload_is_a_valid_non_overlapping_deterministic_scene(name):
    scene = WORKLOADS[name]()
    again = WORKLOADS[name]()
    assert isinstance(scene, collisim.Scene) and scene.fps == 60
    assert scene.world.restitution == 1.0
    scene.world.validate()                     # inside the box
    assert smallest_gap(scene.world) > 0
    assert np.array_equal(scene.world.positions, again.world.positions)
    assert np.array_equal(scene.world.velocities, again.world.velocities)


@pytest.mark.parametrize("name", ["slow_gas", "dense_gas", "fast_gas"])
def test_gases_have_250_particles(name):
    assert WORKLOADS[name]().world.n == 250


def test_gravity_bounce_falls_under_gravity():
    world = WORKLOADS["gravity_bounce"]().world
    assert 1 <= world.n <= 20 and world.gravity[1] < 0 and world.gravity[0] == 0


def test_packings_and_speeds_are_as_named():
    assert packing_fraction(WORKLOADS["dense_gas"]().world) == pytest.approx(0.3, abs=0.01)
    assert packing_fraction(WORKLOADS["slow_gas"]().world) == pytest.approx(0.05, abs=0.005)
    assert mean_radii_per_frame(WORKLOADS["slow_gas"]()) == pytest.approx(0.2, rel=0.1)
    assert mean_radii_per_frame(WORKLOADS["fast_gas"]()) == pytest.approx(2.0, rel=0.1)


def test_pareto_front_keeps_points_no_other_beats_on_both():
    costs = [1.0, 2.0, 3.0, 4.0, 0.5]
    errors = [1.0, 2.0, 0.5, 0.1, 3.0]
    assert accuracy.pareto_front(costs, errors) == [4, 0, 2, 3]


@pytest.fixture(scope="module")
def short_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("accuracy")
    return accuracy.run(out, workloads=["slow_gas"], seconds=1.0, repeats=1, progress=False)


def test_run_writes_every_configuration_to_csv_and_a_chart(short_run):
    with open(short_run["csv"], newline="") as file:
        rows = list(csv.DictReader(file))
    expected = {accuracy.method_label(engine, k) for engine, k in accuracy.configurations()}
    expected.add("pymunk mirror x1 (callbacks)")   # plain pymunk loses nothing at x1 here: no extra row
    assert {row["method"] for row in rows} == expected
    assert len(rows) == len(expected) == 15
    assert {"pymunk x1", "pymunk x32"} <= {row["method"] for row in rows}
    assert set(accuracy.COLUMNS) == set(rows[0])
    png = short_run["png"]["slow_gas"]
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and png.stat().st_size > 10_000


def test_ccd_keeps_the_elastic_gas_apart_and_its_energy(short_run):
    ccd = next(row for row in short_run["rows"] if row["method"] == "ccd")
    assert ccd["lost"] == 0 and ccd["missed"] == 0
    assert ccd["max_overlap"] < 1e-9 and ccd["energy_drift"] < 1e-12   # round-off only


def test_more_discrete_substeps_follow_ccd_more_closely(short_run):
    error = {row["substeps"]: row["position_error"] for row in short_run["rows"] if row["engine"] == "discrete"}
    assert error[64] < error[8] < error[1]
    assert error[64] < 0.1 * error[1]           # first order in dt: 64x smaller steps, far closer


def test_budget_ratio_is_ccd_time_over_pymunk_x1(short_run):
    cost = {row["method"]: row["cost"] for row in short_run["rows"]}
    assert short_run["budget"]["ccd_over_pymunk_x1"]["slow_gas"] == pytest.approx(cost["ccd"] / cost["pymunk x1"])
    assert short_run["budget"]["fast_gas_lossless_pymunk_substeps"] is None   # fast_gas was not run
    assert short_run["budget"]["mirror_over_pymunk_x1"]["slow_gas"] == pytest.approx(
        cost["pymunk mirror x1 (callbacks)"] / cost["pymunk x1"])


def test_pymunk_rows_are_plain_pymunk_and_the_mirror_only_its_own_line(short_run, monkeypatch):
    """The pymunk rows' errors are plain pymunk's recorded run; their time is an unrecorded plain
    run; the mirror is one separately labelled row."""
    scene = WORKLOADS["slow_gas"]().replace(seconds=1.0, broadphase=accuracy.BROADPHASE)
    plain = simulate_plain_pymunk(scene, 1)
    row = next(row for row in short_run["rows"] if row["method"] == "pymunk x1")
    assert row["pair_collisions"] == int(plain.pair_collisions.sum())
    assert row["max_overlap"] == pytest.approx(metrics.max_overlap(plain))
    mirrors = [row for row in short_run["rows"] if row["engine"] == "pymunk_mirror"]
    assert [row["method"] for row in mirrors] == ["pymunk mirror x1 (callbacks)"]
    timed = []
    monkeypatch.setattr(accuracy, "time_plain_pymunk", lambda scene, k: timed.append(k) or 1.0)
    monkeypatch.setattr(accuracy, "run_method", lambda *args: pytest.fail("pymunk timed through run_method"))
    assert accuracy.timed_run(scene, "pymunk", 3) == (None, 1.0) and timed == [3]


def test_lossless_search_tries_every_substep_count_on_the_fast_gas():
    """The first loss-free count is found by trying 1, 2, 3, ... (it need not be one of the grid's
    powers of two), each run recorded with plain pymunk."""
    scene = WORKLOADS["fast_gas"]().replace(seconds=0.5)
    k, tried = accuracy.lossless_substeps(scene)
    assert k is not None and k > 1 and sorted(tried) == list(range(1, k + 1))
    lost = {s: metrics.outside(traj, scene.world)[1] for s, traj in tried.items()}
    assert lost[k] == 0 and all(lost[s] > 0 for s in range(1, k))
    assert all(traj.method == "pymunk" for traj in tried.values())


def test_budget_takes_the_first_loss_free_pymunk_row():
    rows = [dict(workload="fast_gas", method=m, engine=e, substeps=k, cost=c, lost=lost)
            for m, e, k, c, lost in [("ccd", "ccd", 1, 1.0, 0), ("pymunk x1", "pymunk", 1, 0.1, 90),
                                     ("pymunk x4", "pymunk", 4, 0.4, 2), ("pymunk x8", "pymunk", 8, 0.8, 0),
                                     ("pymunk x6", "pymunk", 6, 0.5, 0),
                                     ("pymunk mirror x1 (callbacks)", "pymunk_mirror", 1, 0.3, 80)]]
    figures = accuracy.budget(rows)
    assert figures["fast_gas_lossless_pymunk_substeps"] == 6 == figures["lossless_pymunk_substeps"]["fast_gas"]
    assert figures["fast_gas_ccd_over_lossless_pymunk"] == pytest.approx(2.0)
    assert figures["mirror_over_pymunk_x1"]["fast_gas"] == pytest.approx(3.0)


def test_unknown_workload_is_one_clear_error(tmp_path):
    with pytest.raises(ValueError, match="unknown workload 'nope'"):
        accuracy.run(tmp_path, workloads=["nope"], progress=False)


def test_bench_accuracy_cli_prints_the_budget_ratios(tmp_path, capsys):
    """The command's own main, in this process: the kernels the short run above compiled serve it."""
    from collisim.cli import main
    assert main(["bench", "accuracy", "--workloads", "slow_gas", "--seconds", "0.25", "--repeats", "1",
                 "--no-progress", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "ccd / pymunk x1 on slow_gas:" in out
    assert "pymunk mirror (callbacks) x1 / pymunk x1 on slow_gas:" in out
    assert (tmp_path / "accuracy.csv").exists() and (tmp_path / "accuracy_slow_gas.png").exists()
    assert main(["bench", "accuracy", "--workloads", "lava", "--out", str(tmp_path)]) == 2
    assert "unknown workload 'lava'" in capsys.readouterr().err
