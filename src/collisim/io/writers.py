"""Writers: frames to a video file, written under a temporary name and renamed only when
complete, behind one interface and a registry (WRITERS) the command line reads its choices from.

H.264 (yuv420p) through PyAV plays in every browser; the pip wheels of OpenCV cannot write
H.264, so OpenCV's 'mp4v' is the fallback codec. A new format is a VideoWriter subclass with
_open, _encode and _close, and a row in WRITERS.
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

CRF = {"l": 28, "m": 23, "h": 18}
# x264 speed for each quality: flat-coloured animation compresses well even at fast presets
PRESET = {"l": "ultrafast", "m": "superfast", "h": "veryfast"}


def check_writable(folder: Path) -> None:
    """Create the output folder if needed and prove a file can be written there."""
    try:
        folder.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=folder, prefix=".collisim-probe-"):
            pass
    except OSError as error:
        raise ValueError(f"cannot write to output folder {folder}: {error.strerror or error}") from None


def _temporary_beside(path: Path, suffix: str) -> Path:
    """A new empty file next to `path`, with the permissions a plain open() would give."""
    handle, name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.stem}-", suffix=suffix)
    os.close(handle)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(name, 0o666 & ~umask)
    return Path(name)


def fps_fraction(fps: float) -> Fraction:
    return Fraction(fps).limit_denominator(1001)


class VideoWriter:
    """Context manager that encodes frames on a thread of its own while the caller draws the
    next ones:

        with open_writer("h264", path, fps, size) as video:
            canvas = video.frame_buffer()   # a reusable (height, width, 3) uint8 BGR buffer
            ...draw into canvas...
            video.write(canvas)

    The file appears at `path` only after a clean exit; an error or interrupt removes the
    temporary file. `encode_seconds` is the time the encoder thread spent converting and
    encoding (it overlaps the caller's drawing).
    """

    codec = ""

    @classmethod
    def check(cls) -> None:
        """Raise ValueError when this writer cannot be used on this machine."""

    def __init__(self, path: Path, fps: float, size: tuple, quality: str = "m", buffers: int = 4):
        self.check()
        self.path = Path(path)
        self.fps = fps
        self.width, self.height = size
        self.quality = quality
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
        self.temporary = _temporary_beside(self.path, ".mp4")

    def __enter__(self):
        try:
            self._open()
        except BaseException:
            self.temporary.unlink(missing_ok=True)
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
        self._todo.put(None)
        self._thread.join()
        clean = kind is None and self._error is None
        try:
            self._close(flush=clean)
        finally:
            if clean:
                os.replace(self.temporary, self.path)
            else:
                self.temporary.unlink(missing_ok=True)
        if kind is None:
            self._raise_encoder_error()
        return False

    def _open(self) -> None:
        raise NotImplementedError

    def _encode(self, bgr: np.ndarray) -> None:
        raise NotImplementedError

    def _close(self, flush: bool) -> None:
        raise NotImplementedError


class H264Writer(VideoWriter):
    """H.264 in MP4, yuv420p, through PyAV (libx264)."""

    codec = "h264"

    @classmethod
    def check(cls) -> None:
        import av
        try:
            av.codec.Codec("libx264", "w")
        except Exception:
            raise ValueError("codec h264 is not available (PyAV has no libx264 encoder); try --codec mp4v") from None

    def _open(self) -> None:
        import av
        self._container = av.open(str(self.temporary), mode="w", format="mp4")
        stream = self._container.add_stream("libx264", rate=fps_fraction(self.fps))
        stream.width, stream.height, stream.pix_fmt = self.width, self.height, "yuv420p"
        stream.options = {"crf": str(CRF[self.quality]), "preset": PRESET[self.quality]}
        self._stream = stream
        self._yuv = np.empty((self.height * 3 // 2, self.width), np.uint8)

    def _encode(self, bgr: np.ndarray) -> None:
        import av
        cv2.cvtColor(bgr, cv2.COLOR_BGR2YUV_I420, dst=self._yuv)  # OpenCV converts faster than the encoder's scaler
        frame = av.VideoFrame.from_ndarray(self._yuv, format="yuv420p")
        frame.pts = self._encoded
        self._encoded += 1
        for packet in self._stream.encode(frame):
            self._container.mux(packet)

    def _close(self, flush: bool) -> None:
        if flush:
            for packet in self._stream.encode(None):
                self._container.mux(packet)
        self._container.close()


class Mp4vWriter(VideoWriter):
    """MPEG-4 part 2 in MP4 through OpenCV: the fallback where no H.264 encoder exists."""

    codec = "mp4v"

    def _open(self) -> None:
        fourcc = cv2.VideoWriter_fourcc(*"mp4v")
        self._cv_writer = cv2.VideoWriter(str(self.temporary), fourcc, float(self.fps), (self.width, self.height))
        if not self._cv_writer.isOpened():
            raise ValueError("codec mp4v is not available in this OpenCV build")

    def _encode(self, bgr: np.ndarray) -> None:
        self._cv_writer.write(bgr)

    def _close(self, flush: bool) -> None:
        self._cv_writer.release()


WRITERS = {writer.codec: writer for writer in (H264Writer, Mp4vWriter)}


def writer_for(codec: str) -> type:
    """The writer class of a codec; ValueError if unknown or unavailable here."""
    if codec not in WRITERS:
        raise ValueError(f"unknown codec '{codec}'; choose one of: {', '.join(WRITERS)}")
    WRITERS[codec].check()
    return WRITERS[codec]


def open_writer(codec: str, path, fps: float, size: tuple, quality: str = "m") -> VideoWriter:
    """A VideoWriter for `codec` (use it as a context manager)."""
    return writer_for(codec)(Path(path), fps, size, quality)




def write_png(path: Path, bgr: np.ndarray) -> None:
    """Write a PNG under a temporary name, then rename."""
    name = _temporary_beside(path, ".png")
    try:
        ok, data = cv2.imencode(".png", bgr)
        if not ok:
            raise ValueError(f"could not encode PNG {path}")
        Path(name).write_bytes(data.tobytes())
        os.replace(name, path)
    except BaseException:
        Path(name).unlink(missing_ok=True)
        raise
