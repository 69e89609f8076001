"""Typeset text kept on disk (render/textcache.py): read back to the byte, keyed by all that
shapes it, and never in the way of drawing when the folder or a file is unusable."""
import os
import subprocess
import sys

import matplotlib
import numpy as np
import pytest

from collisim.render import text, textcache


@pytest.fixture
def cache(tmp_path, monkeypatch):
    """An empty cache folder of the test's own, text_image's in-process cache emptied, and no
    text kept yet by this process (as in a new one)."""
    monkeypatch.setenv("COLLISIM_CACHE_DIR", str(tmp_path / "cache"))
    monkeypatch.setattr(textcache, "_kept", 0)
    text.text_image.cache_clear()
    yield tmp_path / "cache" / "text"
    text.text_image.cache_clear()


def no_typesetting(text, size):
    raise AssertionError(f"typeset {text!r} again")


def test_text_typeset_once_is_read_back_the_same_without_typesetting(cache, monkeypatch):
    first = text.text_image(r"the update $p \leftarrow p + v\,\Delta t$", 17.0)
    assert [path.suffix for path in cache.iterdir()] == [".npy"]     # one file, no part file left
    text.text_image.cache_clear()                                  # as a new process would
    monkeypatch.setattr(text, "typeset", no_typesetting)   # text_image lives in render/text.py
    again = text.text_image(r"the update $p \leftarrow p + v\,\Delta t$", 17.0)
    assert again.dtype == np.float32 and np.array_equal(again, first) and first.max() > 0.5


def test_the_file_is_named_by_the_text_its_size_and_the_font_settings(cache):
    names = {textcache.name("p = v t", 17.0), textcache.name("p = v t ", 17.0), textcache.name("p = v t", 17.5)}
    with matplotlib.rc_context({"mathtext.fontset": "stix", "font.family": "serif"}):
        names.add(textcache.name("p = v t", 17.0))
        serif = text.typeset("$x$ and x", 30.0)
    assert len(names) == 4
    assert not np.array_equal(serif, text.typeset("$x$ and x", 30.0))   # so the settings must name it


def test_a_damaged_file_is_typeset_again_and_replaced(cache):
    cache.mkdir(parents=True)
    path = cache / textcache.name("Ag", 17.0)
    path.write_bytes(b"\x93NUMPY cut short")
    image = text.text_image("Ag", 17.0)
    assert np.array_equal(image, text.typeset("Ag", 17.0).astype(np.float32) / 255.0)
    assert np.array_equal(np.load(path), text.typeset("Ag", 17.0))


def test_text_is_drawn_when_the_folder_cannot_be_written(tmp_path, monkeypatch):
    (tmp_path / "blocker").write_text("a file where the folder would be")
    monkeypatch.setenv("COLLISIM_CACHE_DIR", str(tmp_path / "blocker" / "cache"))
    text.text_image.cache_clear()
    try:
        assert text.text_image("p = v t", 17.0).max() > 0.5
    finally:
        text.text_image.cache_clear()
    assert sorted(path.name for path in tmp_path.iterdir()) == ["blocker"]


def test_invalid_mathtext_is_an_error_and_nothing_is_kept(cache):
    with pytest.raises(ValueError, match=r"text '\$x\^2' is not valid mathtext"):
        text.text_image("$x^2", 17.0)
    assert not cache.exists() or list(cache.iterdir()) == []


def test_the_folder_follows_the_environment(monkeypatch, tmp_path):
    monkeypatch.setenv("COLLISIM_CACHE_DIR", str(tmp_path / "mine"))
    assert textcache.folder() == tmp_path / "mine" / "text"
    monkeypatch.delenv("COLLISIM_CACHE_DIR")
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert textcache.folder() == tmp_path / "xdg" / "collisim" / "text"
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert textcache.folder() == tmp_path / "home" / ".cache" / "collisim" / "text"


def test_text_read_back_imports_neither_pyplot_nor_the_agg_backend(tmp_path):
    """The point of the cache: a run whose text is kept never loads what typesetting needs (0.25
    s of a warm first frame), and never pyplot, which would pick a backend for the user."""
    script = ("import sys\nfrom collisim.render import text\ntext.text_image('p = v t', 17.0)\n"
              "print(sorted(m for m in ('matplotlib.pyplot', 'matplotlib.backends.backend_agg') if m in sys.modules))")
    env = dict(os.environ, COLLISIM_CACHE_DIR=str(tmp_path))
    runs = [subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=120)
            for _ in range(2)]
    assert [run.returncode for run in runs] == [0, 0], runs[0].stderr + runs[1].stderr
    assert runs[0].stdout.strip() == "['matplotlib.backends.backend_agg']"   # typeset, the first time
    assert runs[1].stdout.strip() == "[]"


def test_a_run_keeps_the_first_texts_it_typesets_and_no_more(cache, monkeypatch):
    """Text that changes every frame (a live count) does not leave a file a frame."""
    monkeypatch.setattr(textcache, "MOST_PER_RUN", 2)
    for count in range(5):
        assert text.text_image(f"now {count}", 17.0).max() > 0.5
    assert sorted(path.name for path in cache.iterdir()) == sorted(textcache.name(f"now {k}", 17.0) for k in (0, 1))
