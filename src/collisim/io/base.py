"""The writer interface every output format shares: frames are encoded on a thread of their own,
through a pool of reused buffers, into a temporary that is renamed only when complete.

A format is a VideoWriter subclass with _open, _encode(bgr) and _close(flush); io/writers.py
lists them in WRITERS. Also here: the probe that an output folder can be written, single PNG
frames, and the alpha channel of a transparent render.
"""
from __future__ import annotations

import os
import queue
import tempfile
import threading
import time
from fractions import Fraction
from pathlib import Path

import cv2
import numpy as np

from ..core.files import temporary_beside, written_whole


def check_writable(folder: Path) -> list:
    """Create the output folder if needed and prove a file can be written there. Returns the
    folders it created (outermost first), so a failed render can remove them again."""
    folder = Path(folder)
    created = [parent for parent in reversed((folder, *folder.parents)) if not parent.exists()]
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".collisim-probe-"):
            pass
    except OSError as error:
        remove_empty_folders(created)
        raise ValueError(f"cannot write to output folder {folder}: {error.strerror or error}") from None
    return created


def remove_empty_folders(folders: list) -> None:
    """Remove folders (outermost first) that are still empty; leave anything else alone."""
    for folder in reversed(folders):
        try:
            folder.rmdir()
        except OSError:
            return


def fps_fraction(fps: float) -> Fraction:
    return Fraction(fps).limit_denominator(1001)


def alpha_from_background(bgr: np.ndarray, background_bgr: tuple, out: np.ndarray | None = None) -> np.ndarray:
    """The alpha channel (height, width) uint8 of a (height, width, 3) BGR frame: 0 where the
    pixel is exactly the background colour, 255 elsewhere.

    The player draws on an opaque canvas, so the background is recognised by its colour. An
    anti-aliased edge pixel is a blend of a shape's colour and the background: it stays opaque
    with the colour it was drawn with (un-blending it would need the colour it was blended
    from, which a pixel no longer knows). Over another backdrop edges therefore keep a faint
    rim of the background colour, one pixel wide — the same look as the opaque video."""
    mask = cv2.inRange(bgr, background_bgr, background_bgr)   # 255 where equal to the background
    return cv2.bitwise_not(mask, dst=out)


class VideoWriter:
    """Context manager that encodes frames on a thread of its own while the caller draws the
    next ones:

        with open_writer("h264", path, fps, size) as video:
            canvas = video.frame_buffer()   # a reusable (height, width, 3) uint8 BGR buffer
            ...draw into canvas...
            video.write(canvas)

    The output appears at `path` only after a clean exit; an error or interrupt removes the
    temporary. `encode_seconds` is the time the encoder thread spent converting and encoding
    (it overlaps the caller's drawing). With `transparent`, pixels of the `background` colour
    (BGR) become alpha 0 (alpha_from_background); `name` names the files of a sequence."""

    codec = ""         # the name in WRITERS
    suffix = ""        # of the temporary file
    alpha = False      # can write an alpha channel

    @classmethod
    def check(cls) -> None:
        """Raise ValueError when this writer cannot be used on this machine."""

    def __init__(self, path: Path, fps: float, size: tuple, quality: str = "m", *, transparent: bool = False,
                 background: tuple = (0, 0, 0), name: str | None = None, frames: int | None = None,
                 buffers: int = 4):
        self.check()
        if transparent and not self.alpha:
            raise ValueError(f"{self.codec} cannot be transparent")
        self.path = Path(path)
        self.fps = fps
        self.width, self.height = size
        self.quality = quality
        self.transparent, self.background = transparent, tuple(int(c) for c in background)
        self.name, self.expected_frames = name or self.path.stem, frames
        self.frames = 0
        self.encode_seconds = 0.0
        self._free = queue.Queue()
        pool = [np.empty((self.height, self.width, 3), np.uint8) for _ in range(buffers)]
        self._buffer_ids = {id(buffer) for buffer in pool}
        for buffer in pool:
            self._free.put(buffer)
        self._encoded = 0
        self._todo = queue.Queue()
        self._error = None
        self.temporary = None   # made on entering, so that only a `with` block can leave one behind

    def _make_temporary(self) -> Path:
        return temporary_beside(self.path, self.suffix)

    def _publish(self) -> None:
        os.replace(self.temporary, self.path)

    def _discard(self) -> None:
        self.temporary.unlink(missing_ok=True)

    def __enter__(self):
        self.temporary = self._make_temporary()
        try:
            self._open()
        except BaseException:
            self._discard()
            raise
        self._thread = threading.Thread(target=self._encode_loop, name="collisim-encoder", daemon=True)
        self._thread.start()
        return self

    def frame_buffer(self) -> np.ndarray:
        """A free frame buffer to draw into (waits while the encoder holds all of them)."""
        self._raise_encoder_error()
        return self._free.get()

    def write(self, bgr: np.ndarray) -> None:
        """Queue a frame (height, width, 3) uint8 BGR; a buffer from frame_buffer() is handed over
        without a copy, any other array is copied into one."""
        self._raise_encoder_error()
        self._todo.put(bgr if self._owns(bgr) else self._copy_into_buffer(bgr))
        self.frames += 1

    def _owns(self, array) -> bool:
        return array.shape == (self.height, self.width, 3) and id(array) in self._buffer_ids

    def _copy_into_buffer(self, bgr) -> np.ndarray:
        buffer = self.frame_buffer()
        np.copyto(buffer, bgr)
        return buffer

    def _encode_loop(self) -> None:
        while True:
            frame = self._todo.get()
            if frame is None:
                return
            if self._error is None:
                start = time.perf_counter()
                try:
                    self._encode(frame)
                except BaseException as error:  # handed to the drawing thread at its next call
                    self._error = error
                self.encode_seconds += time.perf_counter() - start
            self._free.put(frame)

    def _raise_encoder_error(self) -> None:
        if self._error is not None:
            raise self._error

    def __exit__(self, kind, error, trace):
        published = False
        try:
            self._todo.put(None)
            self._thread.join()
            clean = kind is None and self._error is None
            self._close(flush=clean)
            if clean:
                self._publish()
                published = True
        finally:
            if not published:
                self._thread.join()   # an interrupt may have cut the first join short: let the encoder stop
                self._discard()
        if kind is None:
            self._raise_encoder_error()
        return False

    def _bgra(self, bgr: np.ndarray) -> np.ndarray:
        """The frame with its alpha channel: (height, width, 4) uint8 BGRA."""
        alpha = alpha_from_background(bgr, self.background)
        return cv2.merge((*cv2.split(bgr), alpha))

    def _open(self) -> None:
        raise NotImplementedError

    def _encode(self, bgr: np.ndarray) -> None:
        raise NotImplementedError

    def _close(self, flush: bool) -> None:
        raise NotImplementedError


def write_png(path: Path, bgr: np.ndarray, background: tuple | None = None) -> None:
    """Write one frame as a PNG under a temporary name, then rename. With `background` (BGR) its
    pixels become transparent (an RGBA PNG)."""
    image = bgr if background is None else cv2.merge((*cv2.split(bgr), alpha_from_background(bgr, background)))
    ok, data = cv2.imencode(".png", image)
    if not ok:
        raise ValueError(f"could not encode PNG {path}")
    with written_whole(path, "PNG") as name:
        Path(name).write_bytes(data.tobytes())


def mux(container, stream, frame) -> None:
    """Encode one frame (None flushes the encoder) and write its packets to the container."""
    for packet in stream.encode(frame):
        container.mux(packet)
