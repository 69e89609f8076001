"""Writers: frames to a file, written under a temporary name and renamed only when complete,
behind one interface (io/base.py VideoWriter) and the registry WRITERS the command line reads
its choices from. Which writer makes which format (mp4, webm, gif, mov, png) is io/formats.py.

    h264    H.264 in MP4, yuv420p (PyAV, libx264)            io/encoders.py
    mp4v    MPEG-4 part 2 in MP4 (OpenCV): the fallback     io/encoders.py
    vp9     VP9 in WebM, yuv420p or yuva420p (libvpx-vp9)    io/encoders.py
    prores  ProRes 4444 in MOV, yuv(a)444p10le (prores_ks)   io/encoders.py
    gif     GIF with a palette from the frames               io/gif.py
    png     a PNG per frame in a folder                      io/sequence.py

A new format is a VideoWriter subclass with _open, _encode and _close, a row here and a row in
io/formats.py FORMATS.
"""
from __future__ import annotations

from pathlib import Path

from .base import VideoWriter, check_writable, fps_fraction, remove_empty_folders, write_png
from .encoders import H264Writer, Mp4vWriter, ProResWriter, VP9Writer
from .gif import GifWriter
from .sequence import PngSequenceWriter

WRITERS = {writer.codec: writer for writer in
           (H264Writer, Mp4vWriter, VP9Writer, ProResWriter, GifWriter, PngSequenceWriter)}

__all__ = ["WRITERS", "VideoWriter", "writer_for", "open_writer", "check_writable", "remove_empty_folders",
           "write_png", "fps_fraction"]


def writer_for(codec: str) -> type:
    """The writer class of a codec; ValueError if unknown or unavailable here."""
    if codec not in WRITERS:
        raise ValueError(f"unknown codec '{codec}'; choose one of: {', '.join(WRITERS)}")
    WRITERS[codec].check()
    return WRITERS[codec]


def open_writer(codec: str, path, fps: float, size: tuple, quality: str = "m", **options) -> VideoWriter:
    """A VideoWriter for `codec` (use it as a context manager); options: transparent,
    background (BGR), name (of a sequence's files), frames (expected count)."""
    return writer_for(codec)(Path(path), fps, size, quality, **options)
