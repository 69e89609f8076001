"""A scene declares the video rate its lesson needs (RenderSettings.min_fps): -ql lowers the size
and keeps that rate, and the command says so in one line."""
import pytest

import collisim
from collisim.cli import main
from conftest import decode_video


def test_frame_rate_at_ql_keeps_60_fps_at_480p(tmp_path, capsys):
    out = tmp_path / "frame_rate.mp4"
    assert main(["render", "frame_rate", "-ql", "--seconds", "0.5", "--no-progress", "--out", str(out)]) == 0
    count, width, height, rate, _, _ = decode_video(out)
    assert (count, width, height, rate) == (30, 854, 480, 60)
    notes = [line for line in capsys.readouterr().err.splitlines() if "needs 60 fps" in line]
    assert len(notes) == 1 and "-ql keeps 60 fps" in notes[0]


def test_a_lesson_rate_does_not_override_an_explicit_fps_or_a_faster_quality():
    scene = collisim.load_scene("frame_rate")
    assert collisim.pipeline.plan(scene, fps=15, quality="l").fps == 15     # the user's own choice
    assert collisim.pipeline.plan(scene, quality="k").fps == 60
    with pytest.warns(UserWarning, match="-ql keeps 60 fps"):
        assert collisim.pipeline.plan(scene, quality="l").label == "480p60"     # its default file says so too


def test_min_fps_must_be_a_positive_number():
    with pytest.raises(ValueError, match="min_fps must be a finite number > 0"):
        collisim.RenderSettings(min_fps=0)
