"""collisim.show in a real Jupyter kernel (a notebook built with nbformat, run by nbclient), the
HTML preview of a Trajectory, linked videos, and bad input."""
import base64
import re
import tempfile

import nbformat
import pytest
from jupyter_client.kernelspec import KernelSpecManager
from jupyter_client.manager import KernelManager
from nbclient import NotebookClient

import collisim
from collisim.notebook import PREVIEW_SECONDS, PREVIEW_SIZE, first_seconds
from conftest import decode_video

DATA_URI = re.compile(r'<video [^>]*src="data:video/mp4;base64,([A-Za-z0-9+/=]+)"')


def embedded_video(html: str, tmp_path, name: str = "embedded.mp4"):
    """The MP4 inside a <video> element's data URI, written to tmp_path: its decode_video."""
    match = DATA_URI.search(html)
    assert match, f"no <video> with a data URI in: {html[:200]}"
    path = tmp_path / name
    path.write_bytes(base64.b64decode(match.group(1), validate=True))
    return decode_video(path)


def test_show_in_a_notebook(tmp_path, monkeypatch):
    # the kernel's temporary folders (show keeps the video's for the notebook) go with the test's
    (tmp_path / "kernel-temporary").mkdir()
    monkeypatch.setenv("TMPDIR", str(tmp_path / "kernel-temporary"))
    notebook = nbformat.v4.new_notebook()
    notebook.cells = [
        nbformat.v4.new_code_cell("import collisim"),
        nbformat.v4.new_code_cell('scene = collisim.load_scene("single_bounce").replace(seconds=0.5)\n'
                                  "collisim.show(scene)"),
    ]
    # the kernel is ipykernel's own spec, which runs this interpreter (the venv's), whatever
    # "python3" kernels are registered elsewhere on the machine
    kernel = KernelManager(kernel_name="python3", kernel_spec_manager=KernelSpecManager(kernel_dirs=[]))
    NotebookClient(notebook, km=kernel, timeout=300,
                   resources={"metadata": {"path": str(tmp_path)}}).execute()

    outputs = notebook.cells[-1].outputs
    html = next(o["data"]["text/html"] for o in outputs if "text/html" in o.get("data", {}))
    assert "<video controls autoplay loop muted" in html
    count, width, height, rate, codec, _ = embedded_video(html, tmp_path)
    scene = collisim.load_scene("single_bounce").replace(seconds=0.5)
    assert (count, width, height, codec) == (scene.frames, 640, 360, "h264")


def test_trajectory_shows_a_short_small_preview(tmp_path, monkeypatch):
    scene = collisim.load_scene("two_bodies")
    traj = collisim.simulate(scene.replace(seconds=PREVIEW_SECONDS + 1))
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path / "temporary"))
    (tmp_path / "temporary").mkdir()
    html = traj._repr_html_()
    assert list((tmp_path / "temporary").iterdir()) == []   # the video is in the HTML: nothing is kept
    count, width, height, _, codec, _ = embedded_video(html, tmp_path)
    assert (count, (width, height), codec) == (int(PREVIEW_SECONDS * scene.fps), PREVIEW_SIZE, "h264")


def test_show_links_a_saved_trajectory(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)  # the notebook's folder
    traj = collisim.simulate(collisim.load_scene("two_bodies").replace(seconds=0.5))
    saved = traj.save(tmp_path / "run.npz")
    video = collisim.show(str(saved), size=(160, 90), seconds=0.25, embed=False)
    assert video.path == tmp_path / "renders" / "run.mp4" and not video.embedded
    assert re.search(r'<video controls autoplay loop muted [^>]*src="renders/run\.mp4\?v=\d+"', video._repr_html_())
    assert decode_video(video.path)[:3] == (15, 160, 90)


def test_first_seconds_cuts_frames_and_events():
    traj = collisim.simulate(collisim.load_scene("two_bodies").replace(seconds=2.0))
    cut = first_seconds(traj, 0.5)
    assert cut.frames == 30 and cut.positions.shape == (31, 2, 2)
    assert (cut.positions == traj.positions[:31]).all()
    assert len(cut.events) == (traj.events.time <= traj.times[30]).sum()
    assert first_seconds(traj, 100.0) is traj


@pytest.mark.parametrize("source, message", [
    (42, "show takes a Scene, a Trajectory or the path of a saved trajectory"),
    ([1, 2], "show takes a Scene, a Trajectory or the path of a saved trajectory"),
    ("no_such_run.npz", "cannot read trajectory no_such_run.npz: not found"),
])
def test_show_rejects_bad_sources(source, message, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    with pytest.raises(ValueError, match=re.escape(message)):
        collisim.show(source)


def test_show_rejects_bad_seconds():
    scene = collisim.load_scene("two_bodies")
    with pytest.raises(ValueError, match="seconds must be a finite number > 0"):
        collisim.show(scene, seconds=0)
    with pytest.raises(ValueError, match="seconds must be a finite number > 0"):
        collisim.show(collisim.simulate(scene.replace(seconds=0.1)), seconds=float("nan"))
