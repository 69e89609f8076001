"""Output formats and where a render goes: the format comes from --format or from the extension of
the output, and every mismatch is one clear error before anything is simulated.

    format  extension  writer(s)        pixel format, as FFmpeg decodes it     transparency
    mp4     .mp4       h264 (or mp4v)   yuv420p                                no
    webm    .webm      vp9              yuv420p, yuva420p when transparent     yes (libvpx-vp9 reads the alpha)
    gif     .gif       gif              bgra (the file holds palette indices)  no
    mov     .mov       prores (4444)    yuv444p12le, yuva444p12le              yes
    png     (folder)   png              rgb24, rgba when transparent           yes

ProRes 4444 is written from 10-bit frames (yuv444p10le) and carries 12-bit samples: FFmpeg's
decoder, as editors do, reads it as 12-bit. tests/test_formats_decoded.py decodes every row.
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path


@dataclass(frozen=True)
class Format:
    name: str
    extension: str      # "" for a PNG sequence: its output is a folder
    codecs: tuple       # the writers (io/writers.py WRITERS) that make it; the first is the default
    transparent: bool   # can carry an alpha channel
    what: str           # codec and pixel format, for messages and the README's table
    decodes: tuple = ()  # the pixel format FFmpeg decodes it as: (opaque, transparent or None)
    alpha_decoder: str | None = None   # the decoder that reads its alpha, when FFmpeg's own drops it


FORMATS = {f.name: f for f in (
    Format("mp4", ".mp4", ("h264", "mp4v"), False, "H.264, yuv420p", ("yuv420p", None)),
    Format("webm", ".webm", ("vp9",), True, "VP9, yuv420p (yuva420p when transparent)", ("yuv420p", "yuva420p"),
           alpha_decoder="libvpx-vp9"),
    Format("gif", ".gif", ("gif",), False, "GIF, one palette generated from the frames", ("bgra", None)),
    Format("mov", ".mov", ("prores",), True, "ProRes 4444, 12-bit: decodes as yuv444p12le (yuva444p12le when "
                                            "transparent)", ("yuv444p12le", "yuva444p12le")),
    Format("png", "", ("png",), True, "one PNG per frame in a folder (RGBA when transparent)", ("rgb24", "rgba")),
)}
BY_EXTENSION = {f.extension: f.name for f in FORMATS.values() if f.extension}


def is_folder(out) -> bool:
    """An output given as a folder: a trailing slash, or an existing directory."""
    text = str(out)
    return text.endswith(("/", "\\")) or Path(text).is_dir()


def output_target(out, format: str | None, *, name: str, frame: bool = False) -> tuple:
    """(path, format name) for an output `out` (str or Path):

    - a folder (`DIR/`, or an existing directory) receives `DIR/<name>.<ext>`;
    - a file's extension names its format (.mp4 .webm .gif .mov); --format must agree;
    - a PNG sequence (--format png) is the folder `out` itself, or `DIR/<name>/`;
    - a single frame (`frame`) is a .png file.
    The frame's or the video's path; ValueError for an unknown or mismatched extension."""
    if format is not None and format not in FORMATS:
        raise ValueError(f"unknown format '{format}'; choose one of: {', '.join(FORMATS)}")
    text = str(out)
    if frame:
        if format not in (None, "png"):
            raise ValueError(f"a single frame is written as PNG, not {format}")
        if is_folder(text):
            return Path(text) / f"{name}.png", "png"
        if Path(text).suffix.lower() != ".png":
            raise ValueError(f"a single frame is written as PNG: --out {text} must end in .png (or be a folder)")
        return Path(text), "png"
    if format == "png":
        if text.endswith(("/", "\\")):
            return Path(text) / name, "png"
        if Path(text).suffix:
            raise ValueError(f"a PNG sequence is a folder: give --out a name without extension or DIR/, "
                             f"not {text}")
        return Path(text), "png"
    if is_folder(text):
        return Path(text) / f"{name}{FORMATS[format or 'mp4'].extension}", format or "mp4"
    extension = Path(text).suffix.lower()
    if extension == ".png":
        raise ValueError(f"--out {text}: a .png is one frame (-s or --png FRAME); "
                         f"a PNG sequence is --format png with a folder")
    if extension not in BY_EXTENSION:
        known = ", ".join(BY_EXTENSION)
        what = f"unknown extension '{extension}'" if extension else "no extension"
        raise ValueError(f"--out {text} has {what}; use {known}, or a folder ending in /")
    if format is not None and BY_EXTENSION[extension] != format:
        raise ValueError(f"--format {format} does not match --out {text} (a {extension} file is "
                         f"{BY_EXTENSION[extension]})")
    return Path(text), BY_EXTENSION[extension]


def check_format(format: str, codec: str | None, transparent: bool) -> str:
    """The writer for a format (its default codec, or `codec`): ValueError when the codec does
    not make this format or the format cannot be transparent."""
    spec = FORMATS[format]
    if codec is not None and codec not in spec.codecs:
        owners = [f.name for f in FORMATS.values() if codec in f.codecs]
        if not owners:
            raise ValueError(f"unknown codec '{codec}'; choose one of: {', '.join(FORMATS['mp4'].codecs)}")
        makes = f"always {spec.codecs[0]}" if len(spec.codecs) == 1 else f"one of {', '.join(spec.codecs)}"
        raise ValueError(f"--codec {codec} is for {' and '.join(owners)} only; {format} is {makes}")
    if transparent and not spec.transparent:
        can = ", ".join(f.name for f in FORMATS.values() if f.transparent)
        raise ValueError(f"{format} cannot be transparent; --transparent needs one of: {can}")
    return codec or spec.codecs[0]
