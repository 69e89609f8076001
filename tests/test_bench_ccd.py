"""The ccd benchmark (`collisim bench ccd`): one short run reports ccd against plain pymunk and
events per second that agree with the event counts. Nothing here is timed against a figure."""
import csv

import pytest

import collisim
from collisim.analysis.bench import ccd
from collisim.analysis.bench.workloads import WORKLOADS
from collisim.engine.simulate import METHODS, stream


@pytest.fixture(scope="module")
def short_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("ccd")
    return out, ccd.run(out, workloads=["dense_gas"], sizes=[60], seconds=0.1, repeats=2, progress=False)


def test_rows_hold_the_ratio_and_rate_columns(short_run):
    out, figures = short_run
    (row,) = figures["rows"]
    assert set(ccd.COLUMNS) == set(row)
    assert row["workload"] == "dense_gas" and row["n"] == 60 and row["pymunk_substeps"] >= 1
    assert row["ccd_cost"] > 0 and row["pymunk_cost"] > 0
    assert row["ccd_over_pymunk_low"] <= row["ccd_over_pymunk"] <= row["ccd_over_pymunk_high"]
    assert row["events_per_second_low"] <= row["events_per_second"] <= row["events_per_second_high"]
    assert row["collisions_per_second_low"] <= row["collisions_per_second"] <= row["collisions_per_second_high"]
    with open(figures["csv"]) as file:
        assert [r["workload"] for r in csv.DictReader(file)] == ["dense_gas"]
    assert figures["csv"] == out / "ccd.csv"


def test_collisions_per_second_leave_out_the_cell_crossings(short_run):
    """Collisions per second are the collisions alone over the time, events per second every
    event the loop processed (crossings included), over the same rounds' times."""
    _, figures = short_run
    (row,) = figures["rows"]
    events = row["collisions"] + row["bookkeeping"]
    assert row["collisions"] > 0 and row["bookkeeping"] > 0
    assert row["collisions_per_second"] / row["events_per_second"] == pytest.approx(row["collisions"] / events)
    # every round counts the same events: each rate is events / that round's seconds, so the
    # median time (ccd_cost x simulated seconds) lies between events / fastest and events / slowest
    median_seconds = row["ccd_cost"] * row["seconds"]
    for column, count in (("events_per_second", events), ("collisions_per_second", row["collisions"])):
        assert count / row[column + "_high"] <= median_seconds * (1 + 1e-9)
        assert median_seconds <= count / row[column + "_low"] * (1 + 1e-9)


def test_collisions_counted_are_those_the_trajectory_counts():
    """In an elastic gas every contact solved delivers an impulse, so the stepper's tally of
    collisions equals the trajectory's per-frame collision counts summed."""
    scene = WORKLOADS["dense_gas"](n=60).replace(seconds=0.2, method="ccd")
    stepper = METHODS["ccd"](scene)
    blocks = list(stream(scene, stepper=stepper))
    counted = sum(int(b.wall_collisions.sum() + b.pair_collisions.sum() + b.segment_collisions.sum())
                  for b in blocks)
    tally = stepper.events_processed()
    assert tally["collisions"] == counted > 0
    assert tally["bookkeeping"] > 0
    # the same run through simulate gives the same counts
    traj = collisim.simulate(scene)
    assert int(traj.pair_collisions.sum() + traj.wall_collisions.sum()) == counted


def test_bad_options_are_refused(tmp_path):
    with pytest.raises(ValueError, match="unknown gas"):
        ccd.run(tmp_path, workloads=["gravity_bounce"], sizes=[60])
    with pytest.raises(ValueError):
        ccd.run(tmp_path, workloads=["dense_gas"], sizes=[60], repeats=0)


def test_cli_prints_the_table(cli, tmp_path):
    result = cli("bench", "ccd", "--workloads", "slow_gas", "--sizes", "40", "--seconds", "0.05", "--repeats", "1",
                 "--no-progress", "--out", tmp_path)
    assert result.returncode == 0, result.stderr
    assert "ccd / pymunk" in result.stdout and "collisions/s" in result.stdout and "slow_gas" in result.stdout
    assert (tmp_path / "ccd.csv").exists()
