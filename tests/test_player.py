"""The player draws whatever Trajectory it is given: a scene's stream, a saved run, pymunk's run,
or several runs side by side. Checked on decoded video."""
import gc
import json
import warnings
import zipfile

import numpy as np
import pytest

import collisim
from collisim.analysis.reference import simulate_pymunk
from conftest import decode_video

SIZE = (320, 180)


def decoded_frames(path):
    import av
    with av.open(str(path)) as container:
        return [frame.to_ndarray(format="rgb24") for frame in container.decode(video=0)]


@pytest.fixture(scope="module")
def scene():
    return collisim.load_scene("two_bodies").replace(seconds=1.0)


def test_trajectory_file_round_trip_is_exact(scene, tmp_path):
    traj = collisim.simulate(scene)
    loaded = collisim.load_trajectory(traj.save(tmp_path / "run.npz"))
    for name in ("times", "positions", "velocities", "angles", "angular_velocities", "wall_collisions",
                 "pair_collisions", "segment_collisions", "candidates"):
        np.testing.assert_array_equal(getattr(loaded, name), getattr(traj, name))
    for name in ("time", "kind", "i", "j", "impulse", "point"):
        np.testing.assert_array_equal(getattr(loaded.events, name), getattr(traj.events, name))
    for name in ("positions", "radii", "masses", "colors", "box", "segments", "accelerations"):
        np.testing.assert_array_equal(getattr(loaded.world, name), getattr(traj.world, name))
    assert (loaded.fps, loaded.method, loaded.broadphase, loaded.substeps) == \
        (traj.fps, traj.method, traj.broadphase, traj.substeps)
    assert [p.name for p in tmp_path.iterdir()] == ["run.npz"]   # no temporary left behind


def test_bad_trajectory_files_are_one_clear_error(scene, tmp_path):
    path = collisim.simulate(scene).save(tmp_path / "run.npz")
    with np.load(path) as data:
        arrays = dict(data)
    meta = json.loads(str(arrays["meta"]))
    meta["format"] = 99
    arrays["meta"] = np.array(json.dumps(meta))
    np.savez(tmp_path / "future.npz", **arrays)
    with pytest.raises(ValueError, match="format version 99; this collisim reads version 1"):
        collisim.load_trajectory(tmp_path / "future.npz")
    (tmp_path / "broken.npz").write_bytes(path.read_bytes()[:200])
    (tmp_path / "foreign.npz").write_bytes(b"not a zip at all")
    with zipfile.ZipFile(tmp_path / "empty.npz", "w"):
        pass
    gc.collect()   # what earlier tests in this process left (a notebook kernel's sockets) is not ours
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        for name in ("broken.npz", "foreign.npz", "empty.npz", "missing.npz"):
            with pytest.raises(ValueError, match="cannot read trajectory .*: (not a collisim trajectory file|not found)"):
                collisim.load_trajectory(tmp_path / name)
        gc.collect()
    left_open = [str(w.message) for w in caught if str(tmp_path) in str(w.message)]
    assert left_open == []   # no file left open (a second line on the command line)


@pytest.mark.parametrize("change, words", [
    (lambda a: a.update(frame_positions=a["frame_positions"][:, :1]), "positions has shape"),
    (lambda a: a.update(frame_times=a["frame_times"][:-1]), "has shape"),
    (lambda a: a.update(event_i=a["event_i"] + 1000), "events name bodies outside 0.."),
    (lambda a: a.update(event_point=a["event_point"][:, :1]), "event point has shape")])
def test_a_trajectory_file_whose_arrays_disagree_is_refused(tmp_path, change, words):
    """Edited or mixed-up arrays would otherwise draw something, with no word of what."""
    path = collisim.simulate(collisim.load_scene("particles_250").replace(seconds=0.2)).save(tmp_path / "run.npz")
    with np.load(path) as data:
        arrays = dict(data)
    assert len(arrays["event_i"]) > 0
    change(arrays)
    np.savez(tmp_path / "edited.npz", **arrays)
    with pytest.raises(ValueError, match=f"cannot read trajectory .*edited.npz: its arrays disagree .*{words}"):
        collisim.load_trajectory(tmp_path / "edited.npz")


def test_a_saved_trajectory_renders_the_same_frames_as_the_scene(scene, tmp_path):
    collisim.render(scene, tmp_path / "scene.mp4", SIZE)
    saved = collisim.simulate(scene).save(tmp_path / "run.npz")
    collisim.render(collisim.load_trajectory(saved), tmp_path / "saved.mp4", SIZE, settings=scene.render)
    from_scene, from_file = decoded_frames(tmp_path / "scene.mp4"), decoded_frames(tmp_path / "saved.mp4")
    assert len(from_scene) == len(from_file) == collisim.pipeline.plan(scene, SIZE).frames   # with the slow motion
    for a, b in zip(from_scene, from_file):
        np.testing.assert_array_equal(a, b)


def test_a_pymunk_trajectory_renders_like_any_other(scene, tmp_path):
    traj = simulate_pymunk(scene)
    path = collisim.render(traj, tmp_path / "pymunk.mp4", SIZE)
    count, width, height, rate, codec, pixels = decode_video(path)
    assert (count, width, height, rate, codec, pixels) == (scene.frames, *SIZE, 60, "h264", "yuv420p")
    frame = decoded_frames(path)[30]
    assert frame.std() > 5   # bodies and the box are drawn, not a blank frame


def test_cli_renders_a_saved_trajectory(tmp_path, capsys):
    """The command's own main, in this process (the kernels this file's runs compiled serve it)."""
    from collisim.cli import main
    saved = tmp_path / "bounce.npz"
    assert main(["render", "single_bounce", "--seconds", "0.5", "--size", "160x90", "--no-progress",
                 "--out", str(tmp_path / "a.mp4"), "--save-trajectory", str(saved)]) == 0
    capsys.readouterr()
    assert main(["render", str(saved), "--size", "160x90", "--no-progress", "--out", str(tmp_path / "b.mp4"),
                 "--seconds", "5"]) == 0
    assert decode_video(tmp_path / "b.mp4")[:3] == (30, 160, 90)   # it plays as long as it was simulated...
    assert "ignoring --seconds" in capsys.readouterr().err         # ...and says so
    (tmp_path / "bad.npz").write_text("nonsense")
    assert main(["render", str(tmp_path / "bad.npz"), "--out", str(tmp_path / "c.mp4")]) == 2
    err = capsys.readouterr().err
    assert err.strip().count("\n") == 0 and "Traceback" not in err
    assert "not a collisim trajectory file" in err and not (tmp_path / "c.mp4").exists()


def test_compare_video_plays_the_methods_side_by_side(cli, tmp_path):
    out = tmp_path / "compare.mp4"
    result = cli("compare", "two_bodies", "--seconds", "1", "--video", out)
    assert result.returncode == 0, result.stderr
    assert "pymunk x1" in result.stdout and str(out) in result.stdout
    count, width, height, rate, codec, _ = decode_video(out)
    assert (count, width, height, rate, codec) == (60, 1280, 720, 60, "h264")
    frame = decoded_frames(out)[-1]
    # four panels in a 2 x 2 grid (discrete x1, discrete x8, ccd, pymunk x1): each quarter has its own drawing
    quarters = [frame[r:r + 360, c:c + 640] for r in (0, 360) for c in (0, 640)]
    assert all(q.std() > 5 for q in quarters)


@pytest.mark.parametrize("fps", [15, 30, 60])
def test_the_hud_reaches_its_last_frame_on_the_last_video_frame(fps):
    """The HUD counts frames out of the last sample the video shows, so its last frame reads N/N."""
    from collisim.render.hud import hud_lines
    from collisim.render.timeline import Timeline
    scene = collisim.load_scene("particles_250").replace(seconds=1.0)
    job = collisim.pipeline.plan(scene, SIZE, fps=fps)
    timeline = Timeline(job.chapters, job.size, job.fps)
    canvas = np.empty((SIZE[1], SIZE[0], 3), np.uint8)
    timeline.draw(canvas, job.frames - 1)
    player = timeline._players[0]
    assert player.state.sample == player.last_sample > 0
    line = hud_lines(player._block, player.last_sample, player.state)[0]
    assert f"frame {player.last_sample}/{player.last_sample}" in line


@pytest.mark.parametrize("size", [(854, 480), (1920, 1080)])
def test_the_hud_line_stays_inside_its_panel(size):
    """A long HUD line shrinks to the panel's width (at -qh it grows with the frame first)."""
    from collisim.render.hud import draw_hud
    canvas = np.zeros((size[1], size[0], 3), np.uint8)
    lines = ["t =  1.233 s   frame 74/476 at 60 fps", "discrete | brute (auto)",
             "this frame: 0 candidate pairs, 0 colliding", "collisions so far: 3"]
    draw_hud(canvas, (0, 0, *size), lines, 0.55 * max(1.0, size[1] / 480))
    columns = np.flatnonzero(canvas.any(axis=(0, 2)))
    assert 0 < columns[0] and columns[-1] < size[0] - 5


def test_events_between_is_the_time_window_of_a_run_s_events():
    """The player finds each frame's events by bisection: the same events as a mask over the
    whole block, ties and the window's closed end included."""
    events = collisim.simulate(collisim.load_scene("particles_250").replace(seconds=1.0)).events
    assert len(events) > 100 and np.all(np.diff(events.time) >= 0)
    times = np.concatenate([events.time[::7], events.time[::11] - 1e-9, [-1.0, 0.0, 2.0]])
    for start, end in zip(np.sort(times), np.sort(times)[::-1]):
        for lo, hi in ((start, end), (end, start), (-np.inf, end), (start - 0.12, start)):
            window = events.between(lo, hi)
            mask = (events.time > lo) & (events.time <= hi)
            for name in ("time", "kind", "i", "j", "impulse", "point"):
                np.testing.assert_array_equal(getattr(window, name), getattr(events, name)[mask])


@pytest.mark.parametrize("block", [1, 7, 64])
def test_a_player_s_past_events_are_the_whole_run_s_whatever_the_blocks(block):
    """What an overlay reads in state.events after many blocks is what the run's Trajectory holds."""
    from collisim.engine import stream
    from collisim.model.trajectory import PastEvents
    scene = collisim.load_scene("particles_250").replace(seconds=1.0)
    whole = collisim.simulate(scene).events
    past, capped = PastEvents(), PastEvents(cap=len(whole) // 3)
    for part in stream(scene, block=block):
        past.add(part.events)
        capped.add(part.events)
    assert len(whole) > 100
    middle = float(whole.time[len(whole) // 2])
    upto = int(np.searchsorted(whole.time, middle, side="right"))
    for name in ("time", "kind", "i", "j", "impulse", "point"):
        np.testing.assert_array_equal(getattr(past.up_to(np.inf), name), getattr(whole, name))
        np.testing.assert_array_equal(getattr(past.up_to(middle), name), getattr(whole, name)[:upto])
        np.testing.assert_array_equal(getattr(capped.up_to(np.inf), name), getattr(whole, name)[:len(whole) // 3])
