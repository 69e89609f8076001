"""The video writers of one pass: H.264 in MP4, VP9 in WebM, ProRes 4444 in MOV (through PyAV), and
MPEG-4 part 2 in MP4 through OpenCV, the fallback where PyAV has no H.264 encoder.

The quality letter (l, m, h, k) picks the encoder's constant quality, as manim's presets do.
"""
from __future__ import annotations

import cv2
import numpy as np

from .base import VideoWriter, fps_fraction, mux

# Constant-quality settings per quality letter: lower is better. Flat-coloured animation
# compresses well even at fast presets.
H264_CRF = {"l": 28, "m": 23, "h": 18, "k": 18}
H264_PRESET = {"l": "ultrafast", "m": "superfast", "h": "veryfast", "k": "veryfast"}
VP9_CRF = {"l": 40, "m": 33, "h": 28, "k": 24}
# The alpha plane is coded like the picture, lossily: at the picture's crf a tenth of the background
# comes out slightly opaque and edges ring. A transparent WebM spends more bits to keep it clean.
VP9_ALPHA_CRF = {"l": 24, "m": 20, "h": 16, "k": 12}
# libvpx's realtime mode: higher cpu-used is faster. Its "good" mode makes files about 40 % smaller
# but encodes 5-7 times slower than libx264 (about 4 frames a second at 720p on two cores).
VP9_SPEED = {"l": "8", "m": "8", "h": "7", "k": "6"}


def require_codec(encoder: str, codec: str, hint: str = "") -> None:
    """ValueError when PyAV has no `encoder` (e.g. 'libx264') for the writer `codec`."""
    import av
    try:
        av.codec.Codec(encoder, "w")
    except Exception:
        raise ValueError(f"codec {codec} is not available (PyAV has no {encoder} encoder){hint}") from None


class PyAVWriter(VideoWriter):
    """A one-pass PyAV writer: subclasses name the container, encoder, pixel formats and options.
    Frames are handed to the encoder as BGR (or BGRA when transparent) and converted by its
    scaler, except where a faster conversion is given (_frame)."""

    container = ""
    encoder = ""
    pix_fmt = ""
    alpha_pix_fmt = ""

    @classmethod
    def check(cls) -> None:
        require_codec(cls.encoder, cls.codec)

    def _options(self) -> dict:
        return {}

    def _open(self) -> None:
        import av
        self._container = av.open(str(self.temporary), mode="w", format=self.container)
        stream = self._container.add_stream(self.encoder, rate=fps_fraction(self.fps))
        stream.width, stream.height = self.width, self.height
        stream.pix_fmt = self.alpha_pix_fmt if self.transparent else self.pix_fmt
        stream.options = self._options()
        self._stream = stream

    def _frame(self, bgr: np.ndarray):
        import av
        if self.transparent:
            return av.VideoFrame.from_ndarray(self._bgra(bgr), format="bgra")
        return av.VideoFrame.from_ndarray(bgr, format="bgr24")

    def _encode(self, bgr: np.ndarray) -> None:
        frame = self._frame(bgr)
        frame.pts = self._encoded
        self._encoded += 1
        mux(self._container, self._stream, frame)

    def _close(self, flush: bool) -> None:
        try:
            if flush:
                mux(self._container, self._stream, None)
        finally:
            self._container.close()


class I420Frames:
    """yuv420p frames converted by OpenCV, which is faster than the encoder's scaler."""

    def _open(self) -> None:
        super()._open()
        self._yuv = np.empty((self.height * 3 // 2, self.width), np.uint8)

    def _frame(self, bgr: np.ndarray):
        import av
        if self.transparent:
            return super()._frame(bgr)
        cv2.cvtColor(bgr, cv2.COLOR_BGR2YUV_I420, dst=self._yuv)
        return av.VideoFrame.from_ndarray(self._yuv, format="yuv420p")


class H264Writer(I420Frames, PyAVWriter):
    """H.264 in MP4, yuv420p (libx264): plays in every browser."""

    codec, suffix, container, encoder, pix_fmt = "h264", ".mp4", "mp4", "libx264", "yuv420p"

    @classmethod
    def check(cls) -> None:
        require_codec("libx264", "h264", "; try --codec mp4v")

    def _options(self) -> dict:
        return {"crf": str(H264_CRF[self.quality]), "preset": H264_PRESET[self.quality]}


class VP9Writer(I420Frames, PyAVWriter):
    """VP9 in WebM (libvpx-vp9): yuv420p, or yuva420p with an alpha channel when transparent."""

    codec, suffix, container, encoder = "vp9", ".webm", "webm", "libvpx-vp9"
    pix_fmt, alpha_pix_fmt, alpha = "yuv420p", "yuva420p", True

    def _options(self) -> dict:
        # constant quality (crf with no bitrate cap); row-mt spreads a frame over the cores
        crf = (VP9_ALPHA_CRF if self.transparent else VP9_CRF)[self.quality]
        return {"crf": str(crf), "b": "0", "deadline": "realtime",
                "cpu-used": VP9_SPEED[self.quality], "row-mt": "1"}


class ProResWriter(PyAVWriter):
    """ProRes 4444 in MOV (prores_ks), written from yuv444p10le frames (yuva444p10le with alpha when
    transparent) — the editing format (large files, no generation loss). ProRes 4444 carries
    12-bit samples: FFmpeg decodes the file as yuv444p12le (yuva444p12le)."""

    codec, suffix, container, encoder = "prores", ".mov", "mov", "prores_ks"
    pix_fmt, alpha_pix_fmt, alpha = "yuv444p10le", "yuva444p10le", True

    def _options(self) -> dict:
        return {"profile": "4444", "vendor": "apl0"}


class Mp4vWriter(VideoWriter):
    """MPEG-4 part 2 in MP4 through OpenCV: the fallback where no H.264 encoder exists."""

    codec, suffix = "mp4v", ".mp4"

    def _open(self) -> None:
        fourcc = cv2.VideoWriter_fourcc(*"mp4v")
        self._cv_writer = cv2.VideoWriter(str(self.temporary), fourcc, float(self.fps), (self.width, self.height))
        if not self._cv_writer.isOpened():
            raise ValueError("codec mp4v is not available in this OpenCV build")

    def _encode(self, bgr: np.ndarray) -> None:
        self._cv_writer.write(bgr)

    def _close(self, flush: bool) -> None:
        self._cv_writer.release()
