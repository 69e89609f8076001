"""GIF with one palette generated from all the frames, as manim makes it (ffmpeg's palettegen with
stats_mode=diff, then paletteuse with a Bayer dither), in bounded memory.

manim feeds the frames through a `split` filter into palettegen and paletteuse at once, which
holds every frame in memory until the palette exists. Here the frames make two passes instead:

1. while rendering, each frame goes to palettegen (which keeps only a colour histogram) and to a
   lossless FFV1 spool file, hidden beside the output;
2. when the last frame is in, the palette is read out, the spool is decoded frame by frame
   through paletteuse, and the GIF is encoded; the spool is then removed.

Memory stays flat whatever the length; the disk holds the spool meanwhile (flat animation
compresses well losslessly: about 0.15 MB a frame at 1280x720). GIF timing is in hundredths of
a second: the muxer rounds each frame's time, so the durations alternate (7, 6, 7 cs at 15 fps)
and the whole GIF lasts exactly as long as the video.
"""
from __future__ import annotations

from fractions import Fraction

import numpy as np

from ..core.files import temporary_beside
from .base import VideoWriter, fps_fraction, mux
from .encoders import require_codec

PALETTEGEN = "stats_mode=diff"          # weigh the colours of what moves, as manim does
PALETTEUSE = "dither=bayer:bayer_scale=5:diff_mode=rectangle"


class GifWriter(VideoWriter):
    """GIF (pal8, one global palette of up to 256 colours), through PyAV."""

    codec, suffix = "gif", ".gif"
    spool = None   # the lossless spool file, while it exists

    @classmethod
    def check(cls) -> None:
        import av
        require_codec("gif", "gif")
        require_codec("ffv1", "gif", " for its lossless spool")
        missing = {"palettegen", "paletteuse"} - set(av.filter.filters_available)
        if missing:
            raise ValueError(f"codec gif is not available (PyAV lacks the {', '.join(sorted(missing))} filter)")

    def _open(self) -> None:
        import av
        self._time_base = Fraction(1) / fps_fraction(self.fps)
        self.spool = temporary_beside(self.path, ".spool.mkv")   # removed by _close or _discard
        self._spooler = av.open(str(self.spool), mode="w", format="matroska")
        stream = self._spooler.add_stream("ffv1", rate=fps_fraction(self.fps))
        stream.width, stream.height, stream.pix_fmt = self.width, self.height, "bgr0"
        self._spool_stream = stream
        self._palette_graph, self._palette_in, self._palette_out = self._graph("palettegen", PALETTEGEN)

    def _graph(self, name: str, options: str, palette=None) -> tuple:
        """A filter graph frames -> `name` -> sink; paletteuse also takes the palette frame."""
        import av
        graph = av.filter.Graph()
        frames = graph.add_buffer(width=self.width, height=self.height, format="bgr24", time_base=self._time_base)
        node, sink = graph.add(name, options), graph.add("buffersink")
        frames.link_to(node, 0, 0)
        if palette is not None:
            palette_in = graph.add_buffer(width=palette.width, height=palette.height, format=palette.format.name,
                                          time_base=self._time_base)
            palette_in.link_to(node, 0, 1)
        node.link_to(sink)
        graph.configure()
        if palette is not None:
            palette.pts = 0
            palette_in.push(palette)
            palette_in.push(None)
        return graph, frames, sink

    def _encode(self, bgr: np.ndarray) -> None:
        import av
        frame = av.VideoFrame.from_ndarray(bgr, format="bgr24")
        frame.pts, frame.time_base = self._encoded, self._time_base
        self._encoded += 1
        mux(self._spooler, self._spool_stream, frame)
        self._palette_in.push(frame)

    def _close(self, flush: bool) -> None:
        try:
            if flush:
                mux(self._spooler, self._spool_stream, None)
            self._spooler.close()
            if flush:
                self._palette_in.push(None)
                self._write_gif(self._palette_out.pull())
        finally:
            self.spool.unlink(missing_ok=True)

    def _discard(self) -> None:
        super()._discard()
        if self.spool is not None:
            self.spool.unlink(missing_ok=True)

    def _write_gif(self, palette) -> None:
        """The second pass: the spooled frames through paletteuse into the GIF."""
        import av
        graph, frames_in, frames_out = self._graph("paletteuse", PALETTEUSE, palette)  # graph: alive till done
        with av.open(str(self.temporary), mode="w", format="gif") as gif, av.open(str(self.spool)) as spool:
            stream = gif.add_stream("gif", rate=fps_fraction(self.fps))
            stream.width, stream.height, stream.pix_fmt = self.width, self.height, "pal8"

            def drain():
                while True:
                    try:
                        frame = frames_out.pull()
                    except (av.BlockingIOError, av.EOFError):
                        return
                    mux(gif, stream, frame)

            for pts, frame in enumerate(spool.decode(video=0)):
                image = frame.reformat(format="bgr24")
                image.pts, image.time_base = pts, self._time_base
                frames_in.push(image)
                drain()
            frames_in.push(None)
            drain()
            mux(gif, stream, None)
