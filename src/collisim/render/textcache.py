"""Typeset text kept on disk from one run to the next, as manim keeps its typeset TeX.

A caption's coverage is typeset by matplotlib's mathtext (text.text_image). Its first use
in a process costs about 0.25 s before the first glyph: importing matplotlib's Agg backend
(which mathtext asks for its hinting) and building mathtext's grammar. A warm first frame
with captions took 1.06-1.14 s, and 0.80-0.81 s with its text read from here (single_bounce).

Each text is one .npy file (the uint8 raster mathtext made, bytes as they were), named by a
digest of everything that shapes it: the text, the size, matplotlib's version and its font,
mathtext and text settings (a matplotlibrc that changes the font makes other files). The
folder is $COLLISIM_CACHE_DIR/text, else $XDG_CACHE_HOME/collisim/text, else
~/.cache/collisim/text. The cache only saves time: a folder that cannot be written, or a file
that cannot be read, and the text is typeset as if there were none. A process keeps at most
MOST_PER_RUN new texts, the first it typesets, which the first frames draw: text that changes
every frame (a live count, a time) would otherwise leave a file a frame.
"""
from __future__ import annotations

import contextlib
import hashlib
import os
import tempfile
from pathlib import Path

import numpy as np

FORMAT = 1   # raise when what a file holds, or how it is named, changes
SETTINGS = ("font.", "mathtext.", "text.")   # the rcParams that shape typeset text
MOST_PER_RUN = 256
_kept = 0   # new texts this process has kept


def folder() -> Path:
    """Where typeset text is kept (the module docstring)."""
    root = os.environ.get("COLLISIM_CACHE_DIR")
    if not root:
        base = os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache")
        root = os.path.join(base, "collisim")
    return Path(root) / "text"


def name(text: str, size: float) -> str:
    """The file name of text typeset at size (points at 72 dpi)."""
    import matplotlib
    settings = [(key, str(matplotlib.rcParams[key])) for key in sorted(matplotlib.rcParams)
                if key.startswith(SETTINGS)]   # (by key: reading "backend" would import pyplot)
    described = repr((FORMAT, matplotlib.__version__, text, float(size), settings))
    return hashlib.sha256(described.encode()).hexdigest()[:32] + ".npy"


def path(text: str, size: float) -> Path:
    """Where text typeset at size is kept."""
    return folder() / name(text, size)


def load(kept: Path) -> np.ndarray | None:
    """The raster (h, w) uint8 kept at `kept` (path()), or None."""
    try:
        raster = np.load(kept, allow_pickle=False)
    except (OSError, ValueError, EOFError):   # none yet, unreadable, or cut short
        return None
    ok = raster.dtype == np.uint8 and raster.ndim == 2
    return raster if ok else None


def save(kept: Path, raster: np.ndarray) -> None:
    """Keep raster at `kept` (path()): written whole under a temporary name, then renamed, so a
    process reading at the same time finds the old file, the new one, or none. Past
    MOST_PER_RUN texts kept by this process, nothing is."""
    global _kept
    if _kept >= MOST_PER_RUN:
        return
    _kept += 1
    try:
        kept.parent.mkdir(parents=True, exist_ok=True)
        handle, temporary = tempfile.mkstemp(dir=kept.parent, suffix=".part")
    except OSError:
        return   # a folder that cannot be written: nothing is kept
    try:
        with os.fdopen(handle, "wb") as file:
            np.save(file, np.ascontiguousarray(raster, np.uint8), allow_pickle=False)
        os.replace(temporary, kept)
    except BaseException as error:   # a full disk, or a signal: no part file is left behind
        with contextlib.suppress(OSError):
            os.unlink(temporary)
        if not isinstance(error, OSError):
            raise
