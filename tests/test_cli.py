"""The command line, run in a subprocess as a user would; videos are decoded, not trusted."""
import gc
import subprocess
import sys
import textwrap
from fractions import Fraction

import numpy as np
import pytest

import collisim
from collisim.cli import main
from conftest import decode_video


def test_list_names_every_scene_with_a_description(cli):
    result = cli("list")
    assert result.returncode == 0
    lines = dict(line.split(None, 1) for line in result.stdout.strip().splitlines())
    assert {"single_bounce", "frame_rate"} <= set(lines)
    assert all(len(description) > 10 for description in lines.values())


@pytest.mark.parametrize("codec, name", [("h264", "h264"), ("mp4v", "mpeg4")])
def test_render_writes_a_video_with_the_exact_frames_size_and_rate(cli, tmp_path, codec, name):
    out = tmp_path / "bounce.mp4"
    result = cli("render", "single_bounce", "--seconds", "1.5", "--fps", "30", "--size", "320x240",
                 "--codec", codec, "--out", out)
    assert result.returncode == 0, result.stderr
    count, width, height, rate, codec_name, pix_fmt = decode_video(out)
    assert (count, width, height, rate, codec_name) == (45, 320, 240, Fraction(30), name)
    if codec == "h264":
        assert pix_fmt == "yuv420p"
    assert str(out) in result.stdout and "45 frames" in result.stdout
    assert [p.name for p in tmp_path.iterdir()] == ["bounce.mp4"]     # no temporary left behind


def test_render_by_path_panels_and_odd_size(cli, tmp_path):
    out = tmp_path / "fr.mp4"
    result = cli("render", "scenes/frame_rate.py", "--seconds", "0.5", "--size", "321x181", "--out", out)
    assert result.returncode == 0, result.stderr
    assert "rounded to 322x182" in result.stderr
    assert decode_video(out)[:4] == (30, 322, 182, Fraction(60))


def test_png_frame_is_the_frame_of_the_video(cli, tmp_path):
    import cv2
    result = cli("render", "single_bounce", "--png", "12", "--size", "320x180", "--out", tmp_path / "f.png")
    assert result.returncode == 0, result.stderr
    image = cv2.imread(str(tmp_path / "f.png"))
    assert image.shape == (180, 320, 3) and image.std() > 5


def scene_file(tmp_path, body):
    path = tmp_path / "bad_scene.py"
    path.write_text(textwrap.dedent("""
        \"\"\"A scene for a test.\"\"\"
        import numpy as np
        import collisim

        def scene():
    """) + textwrap.indent(textwrap.dedent(body), "    "))
    return path


GOOD = "return collisim.Scene(world=collisim.World(positions=[[5, 5]], radii=1.0), seconds=0.2)"
BAD_SCENES = {
    "raises": ("1 / 0", "raised ZeroDivisionError"),
    "nan": ("return collisim.Scene(world=collisim.World(positions=[[np.nan, 5]]))", "positions contains NaN or inf"),
    "inf velocity": ("return collisim.Scene(world=collisim.World(positions=[[5, 5]], velocities=[[np.inf, 0]]))",
                     "velocities contains NaN or inf"),
    "radius": ("return collisim.Scene(world=collisim.World(positions=[[5, 5]], radii=0.0))", "radius must be > 0"),
    "mass": ("return collisim.Scene(world=collisim.World(positions=[[5, 5]], masses=[-1.0]))", "mass must be > 0"),
    "outside": ("return collisim.Scene(world=collisim.World(positions=[[11, 5]]))", "beyond the box's right wall"),
    "too large": ("return collisim.Scene(world=collisim.World(positions=[[5, 5]], radii=6))", "larger than the box"),
    "fps": ("return collisim.Scene(world=collisim.World(positions=[[5, 5]]), fps=0)", "fps must be a finite number > 0"),
    "seconds": ("return collisim.Scene(world=collisim.World(positions=[[5, 5]]), seconds=-1)",
                "seconds must be a finite number > 0"),
}


def test_a_scene_that_overflows_gives_one_line_and_no_file(cli, tmp_path):
    path = scene_file(tmp_path, "return collisim.Scene(world=collisim.World(positions=[[5, 5]], gravity=(0, 1e300)),"
                                " seconds=0.5, method='discrete')")
    out = tmp_path / "out" / "video.mp4"
    result = cli("render", path, "--out", out)
    assert result.returncode == 2
    lines = [line for line in result.stderr.strip().splitlines() if "compiling the simulation kernels" not in line]
    assert lines == ["collisim: error: scene 'bad_scene': the discrete method overflowed at frame 1 (t = 0.01667 s): "
                     "a body's position or velocity is no longer a finite number; the scene's speeds, accelerations "
                     "or sizes are too large for double precision"], result.stderr
    assert not out.exists() and not list(tmp_path.rglob("*.mp4*"))


def test_a_scene_whose_own_code_raises_while_drawing_gives_one_line_naming_it_and_no_file(cli, tmp_path):
    """An overlay (the scene's own code) that raises at the fifth frame: one line naming the
    scene's file, line and function, not collisim's traceback."""
    path = scene_file(tmp_path, """
        def boom(canvas, view, state):
            if state.sample > 3:
                return 1 / 0
        world = collisim.World(positions=[[5, 5]], velocities=[[1, 0]])
        return collisim.Scene(world=world, seconds=0.5, render=collisim.RenderSettings(overlay=boom))
    """)
    out = tmp_path / "out" / "video.mp4"
    result = cli("render", path, "--out", out, "--no-progress")
    assert result.returncode == 2
    lines = [line for line in result.stderr.strip().splitlines() if "compiling the simulation kernels" not in line]
    assert lines == ["collisim: error: the scene's code raised ZeroDivisionError: division by zero "
                     "(bad_scene.py, line 10, in boom)"], result.stderr
    assert not out.exists() and not list(tmp_path.rglob("*.mp4*"))


@pytest.mark.parametrize("case", sorted(BAD_SCENES))
def test_bad_scene_gives_one_line_and_no_file(cli, tmp_path, case):
    body, message = BAD_SCENES[case]
    path = scene_file(tmp_path, body)
    out = tmp_path / "out" / "video.mp4"
    result = cli("render", path, "--out", out)
    assert result.returncode == 2
    assert message in result.stderr and len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert "Traceback" not in result.stderr
    assert not (tmp_path / "out").exists()   # nothing written, not even the folder


BAD_OPTIONS = {
    "unknown scene": (["no_such_scene"], "unknown scene 'no_such_scene'"),
    "fps zero": (["single_bounce", "--fps", "0"], "fps must be a finite number > 0"),
    "fps nan": (["single_bounce", "--fps", "nan"], "fps must be a finite number > 0"),
    "seconds negative": (["single_bounce", "--seconds", "-2"], "seconds must be a finite number > 0"),
    "size too small": (["single_bounce", "--size", "40x30"], "too small"),
    "size malformed": (["single_bounce", "--size", "big"], "size must look like 1280x720"),
    "codec": (["single_bounce", "--codec", "xvid"], "invalid choice: 'xvid'"),
    "png frame": (["single_bounce", "--png", "100000"], "out of range"),
    "restitution": (["single_bounce", "--restitution", "1.5"], "restitution must be in [0, 1]"),
}


@pytest.mark.parametrize("case", sorted(BAD_OPTIONS))
def test_bad_option_gives_one_line_and_no_file(cli, tmp_path, case):
    args, message = BAD_OPTIONS[case]
    result = cli("render", *args, "--out", tmp_path / "video.mp4")
    assert result.returncode == 2
    assert message in result.stderr and len(result.stderr.strip().splitlines()) == 1, result.stderr
    assert list(tmp_path.iterdir()) == []


def test_unwritable_output_folder_is_reported_before_simulating(cli, tmp_path):
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    result = cli("render", "single_bounce", "--out", blocker / "video.mp4")
    assert result.returncode == 2 and "cannot write to output folder" in result.stderr
    assert len(result.stderr.strip().splitlines()) == 1


def test_api_raises_value_error_with_the_same_messages(tmp_path, monkeypatch):
    scene = collisim.load_scene("single_bounce")
    with pytest.raises(ValueError, match="too small"):
        collisim.render(scene, tmp_path / "a.mp4", size=(10, 10))
    with pytest.raises(ValueError, match="unknown scene"):
        collisim.load_scene("nope")
    with pytest.raises(ValueError, match="^scene file not found: "):
        collisim.load_scene(tmp_path / "nope.py")
    (tmp_path / "folder.py").mkdir()
    with pytest.raises(ValueError, match=r"^scene file .*folder\.py is a folder, not a file$"):
        collisim.load_scene(tmp_path / "folder.py")
    (tmp_path / "folder.py").rmdir()
    (tmp_path / "sweep.toml").write_text("[grid]\n")   # an existing file that is not a scene file
    with pytest.raises(ValueError, match=r"^.*sweep\.toml is not a scene file: scene files are Python, ending in \.py$"):
        collisim.load_scene(tmp_path / "sweep.toml")
    (tmp_path / "sweep.toml").unlink()
    too_long = "a" * 300   # longer than a file name may be: the system cannot even look it up
    with pytest.raises(ValueError, match=r"^scene file a{300}\.py cannot be looked up: "):
        collisim.load_scene(too_long + ".py")
    with pytest.raises(ValueError, match=r"^unknown scene 'a{300}\.toml'"):
        collisim.load_scene(too_long + ".toml")
    from collisim.analysis.sweep.spec import find_sweep_file
    with pytest.raises(ValueError, match=r"^sweep file a{300}\.toml cannot be looked up: "):
        find_sweep_file(too_long + ".toml")
    with pytest.raises(ValueError, match="fps must be"):
        scene.replace(fps=-1)
    with pytest.raises(ValueError, match="cannot write to output folder"):
        (tmp_path / "f").write_text("")
        collisim.render(scene, tmp_path / "f" / "a.mp4", size=(64, 64))
    import av.codec
    def missing(*args, **kwargs):
        raise av.codec.codec.UnknownCodecError("libx264")
    monkeypatch.setattr(av.codec, "Codec", missing)
    with pytest.raises(ValueError, match="codec h264 is not available"):
        collisim.render(scene.replace(seconds=0.1), tmp_path / "b.mp4", size=(64, 64))
    assert sorted(p.name for p in tmp_path.iterdir()) == ["f"]


def test_interrupted_render_leaves_no_file(tmp_path, monkeypatch):
    from collisim.render import timeline
    calls = {"n": 0}
    original = timeline.draw_frame

    def interrupt(*args, **kwargs):
        calls["n"] += 1
        if calls["n"] == 5:
            raise KeyboardInterrupt
        return original(*args, **kwargs)
    monkeypatch.setattr(timeline, "draw_frame", interrupt)
    with pytest.raises(KeyboardInterrupt):
        collisim.render(collisim.load_scene("single_bounce"), tmp_path / "v.mp4", size=(128, 72))
    assert list(tmp_path.iterdir()) == []


def test_render_api_returns_the_path_and_matches_simulate(tmp_path):
    scene = collisim.load_scene("single_bounce").replace(seconds=0.5)
    path = collisim.render(scene, tmp_path / "x.mp4", size=(160, 90))
    assert path == tmp_path / "x.mp4" and decode_video(path)[:3] == (30, 160, 90)
    traj = collisim.simulate(scene)
    assert traj.positions.shape == (31, 1, 2) and np.all(np.isfinite(traj.positions))


def test_bench_render_reports_the_split_and_the_encode_only_floor(cli, tmp_path):
    import json
    result = cli("bench", "render", "--seconds", "1", "--no-memory", "--no-progress", "--out", tmp_path)
    assert result.returncode == 0, result.stderr
    figures = json.loads((tmp_path / "render.json").read_text())
    assert figures["frames"] == 60 and figures["size"] == [1280, 720]
    assert set(figures["split"]) == {"simulate", "draw", "encode"}
    assert figures["render_over_encode_only"] == pytest.approx(figures["render_seconds"] / figures["encode_only_seconds"])
    assert "render / encode-only" in result.stdout
    assert [row["scene"] for row in figures["stills"]] == ["video_job", "broadphase_six"]
    assert result.stdout.count("-s (the last frame alone)") == 2
    assert sorted(p.name for p in tmp_path.iterdir()) == ["render.json"]   # scratch videos removed


@pytest.mark.parametrize("scene", ["single_bounce", "two_bodies", "particles_250"])
def test_scenes_render_with_either_method(cli, tmp_path, scene):
    for method in ("discrete", "ccd"):
        out = tmp_path / f"{scene}_{method}.mp4"
        result = cli("render", scene, "--method", method, "--seconds", "0.25", "--size", "160x90",
                     "--no-progress", "--out", out)
        assert result.returncode == 0, result.stderr
        paced = collisim.load_scene(scene).with_options(seconds=0.25, method=method)
        frames = collisim.pipeline.plan(paced, (160, 90)).frames   # 15, plus a scene's slow motion
        assert decode_video(out)[:3] == (frames, 160, 90) and frames >= 15



def test_a_reader_that_stops_reading_ends_the_listing_quietly():
    """`collisim list | head -1`: the closed pipe is no error (status 0, nothing on stderr)."""
    process = subprocess.Popen([sys.executable, "-m", "collisim", "list"], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE)
    process.stdout.close()   # the reader is gone before the first line
    err = process.stderr.read().decode()
    assert process.wait(timeout=120) == 0 and err == "", err


def test_the_command_ends_with_mains_status_and_main_leaves_the_callers_collector_alone():
    """cli.run, the `collisim` command: the exit status is main's (0, and 2 with one line for a
    bad scene); main alone, the API, leaves the caller's garbage collector as it was (the
    command freezes its objects at the end so that Python's last collection skips them: a
    library must not do that to its caller)."""
    ends = "import sys; from collisim.cli import run; run(sys.argv[1:])"
    listed = subprocess.run([sys.executable, "-c", ends, "list"], capture_output=True, text=True, timeout=120)
    assert listed.returncode == 0 and "particles_250" in listed.stdout, listed.stderr
    bad = subprocess.run([sys.executable, "-c", ends, "render", "no_such_scene"], capture_output=True, text=True,
                         timeout=120)
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "unknown scene" in bad.stderr, bad.stderr
    frozen = gc.get_freeze_count()
    assert main(["list"]) == 0
    assert gc.get_freeze_count() == frozen
