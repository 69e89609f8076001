"""Output formats, manim's habits, the first-run line, signals and limits — through the command
line in a subprocess, as a user would; every output is decoded, not trusted."""
import os
import re
import signal
import subprocess
import sys
import threading
import time
from fractions import Fraction
from pathlib import Path

import cv2
import numpy as np
import pytest

import collisim
from collisim.pipeline import plan
from collisim.render.timeline import draw_frame, make_players
from conftest import ROOT, as_a_fresh_process, decode_video, run_cli

TINY = ("--seconds", "0.25", "--size", "160x90", "--no-progress")
BACKGROUND_BGR = (28, 20, 18)   # palette.BACKGROUND (18, 20, 28) as BGR


def render(*args, cwd=None, env=None):
    if env is None:
        return run_cli("render", "single_bounce", *args, cwd=cwd)
    return subprocess.run([sys.executable, "-m", "collisim", "render", "single_bounce", *map(str, args)],
                          cwd=cwd or ROOT, capture_output=True, text=True, timeout=600, env=env)


def everything_in(folder):
    """Every name in a folder, hidden ones included."""
    return sorted(os.listdir(folder))


def one_error_line(result):
    lines = result.stderr.strip().splitlines()
    return result.returncode == 2 and len(lines) == 1 and lines[0].startswith("collisim: error: ") \
        and "Traceback" not in result.stderr


# --- every format decoded back -----------------------------------------------------------------

def decode_with_alpha(path, decoder=None):
    """(frames, pixel format, rgba of the last frame) decoding every frame; `decoder` names a
    decoder to use instead of the stream's (libvpx-vp9 reads VP9's alpha channel)."""
    import av
    with av.open(str(path)) as container:
        stream = container.streams.video[0]
        if decoder is None:
            frames = list(container.decode(stream))
        else:
            context = av.CodecContext.create(decoder, "r")
            frames = [frame for packet in container.demux(stream) for frame in context.decode(packet)]
        return len(frames), frames[-1].format.name, frames[-1].to_ndarray(format="rgba")


FORMATS = {  # name: (arguments, codec, pixel format as decoded)
    "mp4": (["--out", "v.mp4"], "h264", "yuv420p"),
    "mp4 mp4v": (["--out", "v.mp4", "--codec", "mp4v"], "mpeg4", "yuv420p"),
    "webm": (["--out", "v.webm"], "vp9", "yuv420p"),
    "mov": (["--format", "mov", "--out", "v.mov"], "prores", "yuv444p12le"),   # ProRes decodes to 12 bits
}


@pytest.mark.parametrize("case", sorted(FORMATS))
def test_each_video_format_decodes_with_its_codec_pixel_format_count_size_and_rate(tmp_path, case):
    args, codec, pix_fmt = FORMATS[case]
    result = render("--fps", "20", *TINY, *args, cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    name = args[args.index("--out") + 1]
    assert decode_video(tmp_path / name) == (5, 160, 90, Fraction(20), codec, pix_fmt)
    assert everything_in(tmp_path) == [name]          # no temporary left behind


def test_transparent_webm_is_vp9_with_an_alpha_channel(tmp_path):
    result = render("--fps", "20", *TINY, "--transparent", "--out", "t.webm", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    count, width, height, rate, codec, _ = decode_video(tmp_path / "t.webm")
    assert (count, width, height, rate, codec) == (5, 160, 90, Fraction(20), "vp9")
    count, pix_fmt, rgba = decode_with_alpha(tmp_path / "t.webm", decoder="libvpx-vp9")
    assert (count, pix_fmt) == (5, "yuva420p")
    # VP9 codes alpha lossily: the background (left of the box) is clear up to coding noise,
    # what is drawn (far from the background colour) opaque
    alpha = rgba[..., 3]
    assert np.percentile(alpha[10:60, :20], 99) <= 8 and alpha.max() == 255
    assert np.median(alpha[np.abs(rgba[..., :3].astype(int) - (18, 20, 28)).sum(axis=2) > 120]) == 255


def test_transparent_mov_is_prores_4444_with_alpha(tmp_path):
    import av
    result = render("--fps", "20", *TINY, "--transparent", "--out", "t.mov", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert decode_video(tmp_path / "t.mov")[:5] == (5, 160, 90, Fraction(20), "prores")
    with av.open(str(tmp_path / "t.mov")) as container:
        assert container.streams.video[0].codec_context.profile == "4444"
    count, pix_fmt, rgba = decode_with_alpha(tmp_path / "t.mov")
    assert count == 5 and pix_fmt.startswith("yuva444p")
    assert rgba[0, 0, 3] == 0 and rgba[..., 3].max() == 255


def test_gif_has_one_palette_and_frame_durations_that_add_up_to_the_video(tmp_path):
    import av
    result = run_cli("render", "single_bounce", "--seconds", "0.4", "--fps", "15", "--size", "160x90",
                     "--no-progress", "--out", tmp_path / "v.gif")
    assert result.returncode == 0, result.stderr
    count, width, height, _, codec, _ = decode_video(tmp_path / "v.gif")
    assert (count, width, height, codec) == (6, 160, 90, "gif")
    with av.open(str(tmp_path / "v.gif")) as container:
        stream = container.streams.video[0]
        durations = [packet.duration for packet in container.demux(stream) if packet.size]
        assert stream.time_base == Fraction(1, 100)
    assert len(durations) == 6 and set(durations) <= {6, 7} and sum(durations) == 40   # 1/15 s each, 0.4 s in all
    assert everything_in(tmp_path) == ["v.gif"]        # the lossless spool is gone


def test_gif_over_50_fps_says_browsers_slow_it(tmp_path):
    result = render("--fps", "60", *TINY, "--out", tmp_path / "v.gif")
    assert result.returncode == 0 and "collisim: note: a GIF at 60 fps plays slower" in result.stderr


@pytest.mark.parametrize("transparent", [False, True])
def test_png_sequence_has_one_file_per_frame_rgba_when_transparent(tmp_path, transparent):
    extra = ["--transparent"] if transparent else []
    result = render("--fps", "20", *TINY, "--format", "png", "--out", tmp_path / "seq", *extra)
    assert result.returncode == 0, result.stderr
    assert everything_in(tmp_path) == ["seq"]
    names = everything_in(tmp_path / "seq")
    assert names == [f"single_bounce_{k:04d}.png" for k in range(5)]
    image = cv2.imread(str(tmp_path / "seq" / names[-1]), cv2.IMREAD_UNCHANGED)
    assert image.shape == ((90, 160, 4) if transparent else (90, 160, 3))
    if transparent:
        background = np.all(image[..., :3] == BACKGROUND_BGR, axis=2)
        assert background.mean() > 0.5
        np.testing.assert_array_equal(image[..., 3], np.where(background, 0, 255))


def test_png_sequence_replaces_an_earlier_one_and_refuses_a_folder_of_other_files(tmp_path):
    seq = tmp_path / "seq"
    assert render("--fps", "20", *TINY, "--format", "png", "--out", seq).returncode == 0
    (seq / "single_bounce_0099.png").write_bytes(b"stale")
    assert render("--fps", "12", *TINY, "--format", "png", "--out", seq).returncode == 0
    assert len(everything_in(seq)) == 3 and everything_in(tmp_path) == ["seq"]
    (seq / "notes.txt").write_text("mine")
    result = render("--fps", "12", *TINY, "--format", "png", "--out", seq)
    assert one_error_line(result) and "holds other files" in result.stderr
    assert "notes.txt" in everything_in(seq)


def test_last_frame_is_the_sequence_s_last_frame(tmp_path):
    assert render("--fps", "20", *TINY, "--format", "png", "--out", tmp_path / "seq").returncode == 0
    result = render("--fps", "20", *TINY, "-s", "--out", tmp_path / "last.png")
    assert result.returncode == 0, result.stderr
    assert "frame 4" in result.stdout
    last = cv2.imread(str(tmp_path / "last.png"))
    np.testing.assert_array_equal(last, cv2.imread(str(tmp_path / "seq" / "single_bounce_0004.png")))


# --- manim's habits ----------------------------------------------------------------------------

QUALITIES = {"-ql": ("480p15", 854, 480, 15), "-qm": ("720p30", 1280, 720, 30),
             "-qh": ("1080p60", 1920, 1080, 60), "-qk": ("2160p60", 3840, 2160, 60)}


@pytest.mark.parametrize("flag", sorted(QUALITIES))
def test_quality_presets_set_size_and_video_rate_and_name_the_default_output(tmp_path, flag):
    label, width, height, fps = QUALITIES[flag]
    seconds = "0.0333333333333" if flag == "-qk" else "0.2"   # -qk: two frames of 3840x2160
    result = render(flag, "--seconds", seconds, "--no-progress", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    out = tmp_path / "renders" / "single_bounce" / f"{label}.mp4"
    assert decode_video(out)[:4] == (round(float(seconds) * fps), width, height, Fraction(fps))
    assert everything_in(out.parent) == [out.name]


def test_long_quality_option_is_the_same_preset_and_size_names_the_output(tmp_path):
    result = render("--quality", "l", "--seconds", "0.2", "--no-progress", cwd=tmp_path)
    assert result.returncode == 0, result.stderr
    assert decode_video(tmp_path / "renders/single_bounce/480p15.mp4")[:4] == (3, 854, 480, Fraction(15))
    assert render(*TINY, cwd=tmp_path).returncode == 0             # --size: WxH, the scene's 60 fps
    assert decode_video(tmp_path / "renders/single_bounce/160x90.mp4")[:4] == (15, 160, 90, Fraction(60))
    assert render("--seconds", "0.1", "--no-progress", "-s", cwd=tmp_path).returncode == 0
    assert cv2.imread(str(tmp_path / "renders/single_bounce/720p60.png")).shape == (720, 1280, 3)


def test_out_folder_receives_scene_named_files_and_new_folders_are_made(tmp_path):
    assert render(*TINY, "--out", f"{tmp_path}/").returncode == 0                  # DIR/
    assert render(*TINY, "--out", tmp_path, "--format", "webm").returncode == 0    # an existing directory
    assert render(*TINY, "--out", f"{tmp_path}/new/deeper/", "--format", "gif").returncode == 0
    assert everything_in(tmp_path) == ["new", "single_bounce.mp4", "single_bounce.webm"]
    assert everything_in(tmp_path / "new" / "deeper") == ["single_bounce.gif"]
    assert decode_video(tmp_path / "single_bounce.webm")[4] == "vp9"


BAD_OUTPUTS = {
    "mismatched extension": (["--format", "webm", "--out", "v.mp4"], "--format webm does not match"),
    "unknown extension": (["--out", "v.avi"], "unknown extension '.avi'"),
    "no extension": (["--out", "video"], "has no extension"),
    "png without -s": (["--out", "v.png"], "a .png is one frame"),
    "frame to a video": (["-s", "--out", "v.mp4"], "must end in .png"),
    "transparent mp4": (["--transparent", "--out", "v.mp4"], "mp4 cannot be transparent"),
    "transparent gif": (["--transparent", "--out", "v.gif"], "gif cannot be transparent"),
    "codec of another format": (["--codec", "mp4v", "--out", "v.webm"], "--codec mp4v is for mp4 only"),
    "unwritable folder": (["--out", "blocker/new/v.mp4"], "cannot write to output folder"),
    "unwritable new folder": (["--out", "blocker/new/"], "cannot write to output folder"),
    "background": (["--background", "red", "--out", "v.mp4"], "background must look like #1a2b3c"),
    "both frames": (["-s", "--png", "3", "--out", "v.png"], "not both"),
}


@pytest.mark.parametrize("case", sorted(BAD_OUTPUTS))
def test_bad_output_is_one_line_nothing_written_and_nothing_simulated(tmp_path, monkeypatch, capsys, case):
    """The command's own main, in this process: the output is checked before the scene is
    simulated (a subprocess's one line and exit status are checked by the limits test below)."""
    from collisim import cli, pipeline

    def no_simulation(scene, *args, **kwargs):
        raise AssertionError("simulated before the output was checked")
    monkeypatch.setattr(pipeline, "stream", no_simulation)
    monkeypatch.chdir(tmp_path)
    args, message = BAD_OUTPUTS[case]
    (tmp_path / "blocker").write_text("a file, not a folder")
    assert cli.main(["render", str(ROOT / "scenes/single_bounce.py"), *TINY, *args]) == 2
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("collisim: error: ") and message in lines[0], lines
    assert everything_in(tmp_path) == ["blocker"]


def test_theme_and_background_colour_the_canvas(tmp_path):
    assert render(*TINY, "-s", "--background", "#ff0000", "--out", tmp_path / "red.png").returncode == 0
    assert render(*TINY, "-s", "--theme", "light", "--out", tmp_path / "light.png").returncode == 0
    assert tuple(cv2.imread(str(tmp_path / "red.png"))[0, 0]) == (0, 0, 255)
    assert cv2.imread(str(tmp_path / "light.png"))[0, 0].min() > 200


def test_version():
    result = run_cli("--version")
    assert result.returncode == 0 and result.stdout.strip() == f"collisim {collisim.__version__}"


PANEL_SCENE = '''"""Two circles in a panel of their own."""
import collisim


def scene():
    world = collisim.World([[2.0, 2.0], [6.0, 2.0]], velocities=[[1.0, 0.0], [-1.0, 0.0]], radii=0.5,
                           box=(0, 0, 8, 4))
    return collisim.Scene(panels=[collisim.Panel(collisim.Scene(world=world, fps=60, seconds=1.0), "two")],
                          fps=60, seconds=1.0)
'''


def test_panel_scene_says_which_physics_flags_it_ignores(tmp_path):
    """A scene of panels of its own (two circles in a box: the kernels of the shipped two-body
    scenes, not a map's) is rendered by its path."""
    (tmp_path / "panels.py").write_text(PANEL_SCENE)
    result = run_cli("render", tmp_path / "panels.py", "--seconds", "0.4", "--size", "160x90", "--no-progress",
                     "--method", "ccd", "--substeps", "2", "--out", tmp_path / "f.mp4")
    assert result.returncode == 0, result.stderr
    notes = [line for line in result.stderr.splitlines() if line.startswith("collisim: note: ") and "--" in line]
    assert len(notes) == 1 and "panels that keep their own physics" in notes[0]
    assert "ignoring --method, --substeps" in notes[0]
    assert decode_video(tmp_path / "f.mp4")[:3] == (24, 160, 90)


# --- the video's frame rate and the simulation's step --------------------------------------------

def shown_states(job, frames):
    """(time, positions) the first panel shows at each video frame of a plan."""
    players = make_players(job.chapters[0], job.size, job.fps)
    canvas = np.zeros((job.size[1], job.size[0], 3), np.uint8)
    shown = []
    for frame in range(frames):
        draw_frame(canvas, players, frame)
        shown.append((players[0].state.time, players[0].state.positions.copy()))
    return shown


def test_video_fps_samples_one_simulation_at_the_scene_s_own_step():
    scene = collisim.load_scene("particles_250").replace(seconds=1.0)   # a scene without slow motion
    at30, at60 = plan(scene, (320, 180), fps=30), plan(scene, (320, 180), fps=60)
    assert (at30.frames, at60.frames) == (30, 60)
    assert [p.fps for p in at30.chapters[0].panels] == [scene.fps]       # the step is the scene's
    shown30, shown60 = shown_states(at30, 30), shown_states(at60, 60)
    reference = collisim.simulate(scene)
    for k in range(30):
        (t30, p30), (t60, p60) = shown30[k], shown60[2 * k]
        assert t30 == t60 == pytest.approx(k / 30, abs=1e-12)
        np.testing.assert_allclose(p30, p60, rtol=0, atol=1e-12)
        np.testing.assert_allclose(p30, reference.positions[2 * k], rtol=0, atol=1e-12)
    assert plan(scene, quality="l").fps == 15 and plan(scene, quality="l").chapters[0].panels[0].fps == scene.fps


def test_fps_sets_the_video_and_physics_fps_the_step(tmp_path):
    result = render("--fps", "30", *TINY, "--out", tmp_path / "v30.mp4")
    assert result.returncode == 0 and decode_video(tmp_path / "v30.mp4")[:4] == (8, 160, 90, Fraction(30))
    result = render("--physics-fps", "240", *TINY, "--out", tmp_path / "p240.mp4")
    assert result.returncode == 0 and decode_video(tmp_path / "p240.mp4")[:4] == (15, 160, 90, Fraction(60))


# --- limits ------------------------------------------------------------------------------------

def test_size_and_frame_limits_and_no_limits(tmp_path):
    result = render("--size", "7700x64", "--seconds", "0.05", "--out", tmp_path / "wide.mp4")
    assert one_error_line(result) and "larger than 7680x4320" in result.stderr and "--no-limits" in result.stderr
    result = render("--seconds", "1700", "--out", tmp_path / "long.mp4")        # 102 000 frames at 60 fps
    assert one_error_line(result) and "102000 frames, more than 100000" in result.stderr
    result = render("--physics-fps", "1e12", "--out", tmp_path / "fine.mp4")     # ran for ever
    assert one_error_line(result) and ("would take 8000000000000 simulation steps (8000000000000 frames at 1e+12 "
                                       "fps), more than 10000000; use --no-limits") in result.stderr, result.stderr
    result = render("--substeps", "100000", "--out", tmp_path / "fine.mp4")
    assert one_error_line(result) and "48000000 simulation steps (480 frames at 60 fps of 100000 substeps)" in result.stderr
    assert everything_in(tmp_path) == []
    result = render("--size", "7700x64", "--seconds", "0.05", "--no-limits", "--no-progress",
                    "--out", tmp_path / "wide.mp4")
    assert result.returncode == 0, result.stderr
    assert decode_video(tmp_path / "wide.mp4")[:3] == (3, 7700, 64)
    result = render("--seconds", "1700", "--png", "0", "--no-limits", "--size", "160x90", "--out", tmp_path / "f.png")
    assert result.returncode == 0, result.stderr
    assert everything_in(tmp_path) == ["f.png", "wide.mp4"]


# --- signals -------------------------------------------------------------------------------------

BAR = re.compile(r"\d+/\d+ \[")


@pytest.mark.parametrize("name, number, out", [
    ("SIGTERM", signal.SIGTERM, "v.mp4"), ("SIGHUP", signal.SIGHUP, "v.gif"),
    ("SIGTERM", signal.SIGTERM, "seq"), ("SIGINT", signal.SIGINT, "v.webm")])
def test_signal_mid_render_leaves_no_file_and_says_so(tmp_path, name, number, out):
    folder = tmp_path / "out"
    folder.mkdir()
    extra = ["--format", "png"] if out == "seq" else []
    process = subprocess.Popen(
        [sys.executable, "-m", "collisim", "render", "particles_250", "--seconds", "60", "--size", "320x180",
         *extra, "--out", str(folder / out)], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        preexec_fn=as_a_fresh_process)
    seen = bytearray()
    reader = threading.Thread(target=lambda: [seen.extend(chunk) for chunk in iter(
        lambda: os.read(process.stderr.fileno(), 4096), b"")], daemon=True)
    reader.start()
    deadline = time.monotonic() + 240
    while not BAR.search(seen.decode(errors="replace")) and process.poll() is None and time.monotonic() < deadline:
        time.sleep(0.05)
    assert process.poll() is None, seen.decode(errors="replace")
    time.sleep(0.3)
    process.send_signal(number)
    status = process.wait(timeout=60)
    reader.join(timeout=10)
    process.stdout.close()
    process.stderr.close()
    stderr = seen.decode(errors="replace")
    assert status == 128 + number, stderr
    last_line = stderr.rstrip("\n").split("\n")[-1].split("\r")[-1]   # what the terminal shows last
    assert last_line == f"collisim: interrupted ({name}); no file written", stderr
    assert "Traceback" not in stderr
    assert everything_in(folder) == []


# --- the first run -------------------------------------------------------------------------------

COMPILING = "collisim: compiling the simulation kernels (first run only)"


def test_a_warm_cache_says_nothing_about_compiling(tmp_path):
    render(*TINY, "--out", tmp_path / "a.mp4")            # makes sure the kernels are cached
    result = render(*TINY[:-1], "--out", tmp_path / "b.mp4")
    assert result.returncode == 0 and COMPILING not in result.stderr, result.stderr
    assert "compiling" not in result.stdout


def cache_missing_one_kernel(cache: Path, missing: str = "discrete.run_frames_from_python") -> bool:
    """Fill the folder `cache` (a NUMBA_CACHE_DIR) with the kernels this process's renders cached
    (collisim keeps them in core/compiling.cache_folder(), under NUMBA_CACHE_DIR as
    collisim-DIGEST), less the entries of `missing` (module.function), a kernel a render calls
    before its first frame. False when there is nothing to copy."""
    import shutil

    import numba
    from collisim.core.compiling import PACKAGE, package_digest
    kept = Path(numba.config.CACHE_DIR)
    target = cache / f"collisim-{package_digest(PACKAGE)[:20]}"
    copied = False
    for entry in [*kept.rglob("*.nbi"), *kept.rglob("*.nbc")]:
        if entry.name.startswith(f"{missing}-"):
            continue
        folder = target / entry.parent.relative_to(kept)
        folder.mkdir(parents=True, exist_ok=True)
        shutil.copy2(entry, folder / entry.name)
        copied = True
    return copied


def test_a_kernel_missing_from_the_cache_says_it_is_compiling_before_the_bar(tmp_path):
    """The first-run line comes from numba's compile events, whatever compiles: a cache with one
    kernel missing shows it as an empty cache does (an empty cache took 35 s to fill here, and
    the Quick start's first render runs with one on every fresh install)."""
    render(*TINY, "--out", tmp_path / "warm_tree.mp4")            # the cache holds every kernel it needs
    cache = tmp_path / "cache"
    assert cache_missing_one_kernel(cache)
    env = dict(os.environ, NUMBA_CACHE_DIR=str(cache))
    cold = render("--seconds", "0.25", "--size", "160x90", "--out", tmp_path / "cold.mp4", env=env)
    assert cold.returncode == 0, cold.stderr
    assert cold.stderr.count(COMPILING) == 1
    bar = BAR.search(cold.stderr)
    assert bar is not None and cold.stderr.index(COMPILING) < bar.start()       # the line comes first
    seconds = re.search(r"(\d+\.\d) s \((\d+\.\d) s compiling\)$", cold.stdout.strip())
    assert seconds and float(seconds[1]) >= float(seconds[2]) > 0             # the whole wall time, compile in it
    assert any(cache.rglob("discrete.run_frames_from_python-*.nbi"))             # the kernel compiled is now cached
    warm = render("--seconds", "0.25", "--size", "160x90", "--out", tmp_path / "warm.mp4", env=env)
    assert warm.returncode == 0 and COMPILING not in warm.stderr, warm.stderr


def test_a_compile_during_the_render_clears_the_bar_once_and_stays_out_of_its_clock():
    import io

    import numba
    from collisim.render.video import Progress
    stream = io.StringIO()
    with Progress(bar=True, stream=stream) as progress:
        progress.step(100, "v.mp4")
        numba.njit(lambda x: x * 3 + 1)(2)            # a kernel no cache holds: numba compiles it
        numba.njit(lambda x: x * 5 - 1)(2)
        assert progress.compiled and progress.compile_seconds > 0
        assert progress.bar.format_dict["elapsed"] < progress.compile_seconds   # rate and ETA leave it out
        progress.step(100, "v.mp4")
    assert stream.getvalue().count(COMPILING) == 1
    assert "\r" + COMPILING in stream.getvalue()      # on a cleared line, not after the bar's text
