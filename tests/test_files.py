"""Files collisim writes (files.py): whole or not at all, with plain permissions, and a file system
error is one line naming the file, never a temporary's name."""
import csv
import os
import stat

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

import collisim
from collisim.core.files import save_figure, write_table, write_text, written_whole
from collisim.model.trajectory import load_trajectory


@pytest.fixture(scope="module")
def trajectory():
    return collisim.simulate(collisim.load_scene("two_bodies").replace(seconds=0.1))


def plain_mode(folder):
    """The permission bits a plain open() gives a new file in folder (under this process's umask)."""
    probe = folder / "plain"
    probe.write_bytes(b"")
    mode = stat.S_IMODE(os.stat(probe).st_mode)
    probe.unlink()
    return mode


def test_a_saved_trajectory_has_the_permissions_of_a_plain_file_and_loads(tmp_path, trajectory):
    path = trajectory.save(tmp_path / "run.npz")
    assert stat.S_IMODE(os.stat(path).st_mode) == plain_mode(tmp_path)
    np.testing.assert_array_equal(load_trajectory(path).positions, trajectory.positions)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["run.npz"]


@pytest.mark.parametrize("where", ["missing folder", "a folder"])
def test_saving_where_no_file_can_be_is_one_line_naming_the_file(tmp_path, trajectory, where):
    path = tmp_path / "missing" / "run.npz" if where == "missing folder" else tmp_path / "taken"
    if where == "a folder":
        path.mkdir()
    with pytest.raises(ValueError) as raised:
        trajectory.save(path)
    message = str(raised.value)
    assert message.startswith(f"cannot write trajectory {path}: ") and "\n" not in message
    assert ".run-" not in message and ".taken-" not in message   # no temporary's name
    assert [p.name for p in tmp_path.rglob("*") if p.is_file()] == []


def test_an_interrupted_write_leaves_the_earlier_file_and_no_temporary(tmp_path):
    path = write_text(tmp_path / "figures.json", "earlier")
    with pytest.raises(KeyboardInterrupt):
        with written_whole(path, "figures") as temporary:
            temporary.write_text("half")
            raise KeyboardInterrupt
    assert path.read_text() == "earlier"
    assert [p.name for p in tmp_path.iterdir()] == ["figures.json"]


def test_a_table_and_a_chart_are_written_whole_with_plain_permissions(tmp_path):
    rows = [{"n": 1, "ratio": 0.5}, {"n": 10, "ratio": 0.25}]
    table = write_table(tmp_path / "t.csv", rows, ["n", "ratio"])
    with open(table, newline="") as file:
        assert list(csv.DictReader(file)) == [{"n": "1", "ratio": "0.5"}, {"n": "10", "ratio": "0.25"}]
    figure = Figure(figsize=(2, 2))
    FigureCanvasAgg(figure)
    figure.subplots().plot([0, 1], [1, 0])
    chart = save_figure(figure, tmp_path / "c.png")
    assert chart.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    for path in (table, chart):
        assert stat.S_IMODE(os.stat(path).st_mode) == plain_mode(tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["c.png", "t.csv"]
