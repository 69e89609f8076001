"""Where a render goes: renders of different physics keep files of their own, and manim's
-o NAME, -t and -r W,H do what they do in manim. Through collisim.cli.main, every file decoded."""
from fractions import Fraction

import cv2
import pytest

from collisim.cli import main
from conftest import decode_video

SHORT = ["-ql", "--seconds", "0.2", "--no-progress"]


def render(*args):
    return main(["render", "single_bounce", *SHORT, *map(str, args)])


@pytest.fixture
def here(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    return tmp_path / "renders" / "single_bounce"


def test_renders_of_different_physics_do_not_overwrite_each_other(here):
    assert render() == 0
    plain = (here / "480p15.mp4").read_bytes()
    assert render("--physics-fps", "30") == 0
    assert render("--method", "ccd") == 0
    assert render("--restitution", "0.9", "--substeps", "4") == 0
    assert render("--method", "discrete") == 0          # the scene's own method: the same physics, the same file
    assert sorted(p.name for p in here.iterdir()) == ["480p15.mp4", "480p15_ccd.mp4", "480p15_physics30.mp4",
                                                      "480p15_x4_e0p9.mp4"]
    assert (here / "480p15.mp4").read_bytes() == plain  # same input, same bytes, and not overwritten
    for name in ("480p15.mp4", "480p15_physics30.mp4", "480p15_ccd.mp4"):
        assert decode_video(here / name)[:4] == (3, 854, 480, Fraction(15))


def test_a_png_sequence_of_changed_physics_is_a_folder_of_its_own(here):
    assert render("--format", "png", "--restitution", "0.5") == 0
    assert [p.name for p in here.iterdir()] == ["480p15_e0p5"] and len(list((here / "480p15_e0p5").iterdir())) == 3


def test_output_file_names_the_file_in_the_scene_s_folder_as_manim_does(here):
    assert render("-o", "take1") == 0
    assert render("--output_file", "take2.webm") == 0          # a video extension names the format
    assert render("-o", "last", "-s") == 0
    assert render("-o", "seq", "--format", "png") == 0
    assert sorted(p.name for p in here.iterdir()) == ["last.png", "seq", "take1.mp4", "take2.webm"]
    assert decode_video(here / "take2.webm")[4] == "vp9"
    assert cv2.imread(str(here / "last.png")).shape == (480, 854, 3)


def test_t_is_transparent_and_r_is_the_resolution(here):
    assert render("-t", "-s", "-r", "320,180") == 0
    rgba = cv2.imread(str(here / "320x180.png"), cv2.IMREAD_UNCHANGED)
    assert rgba.shape == (180, 320, 4) and rgba[0, 0, 3] == 0 and rgba[..., 3].max() == 255
    assert render("--resolution", "256;144", "-o", "small") == 0     # manim also splits on ';' and '-'
    assert decode_video(here / "small.mp4")[1:3] == (256, 144)


@pytest.mark.parametrize("args, message", [
    (["-r", "320"], "resolution must look like 1280,720"),
    (["-r", "320x180"], "resolution must look like 1280,720"),
    (["-o", "a", "--out", "b.mp4"], "choose one output"),
    (["-o", "/tmp/x.mp4"], "-o takes a file name"),
])
def test_bad_output_flags_are_one_line_and_write_nothing(here, capsys, args, message):
    try:
        status = render(*args)
    except SystemExit as exit:
        status = exit.code
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1 and message in err[0]
    assert not here.exists()
