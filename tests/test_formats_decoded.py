"""Every row of the format table (io/formats.py FORMATS, the README's table) decoded: each format,
opaque and transparent where it can be, decodes as the pixel format the table states."""
import av
import pytest

from collisim.cli import main
from collisim.io.formats import FORMATS

CASES = [(name, codec, transparent) for name, f in FORMATS.items() for codec in f.codecs
         for transparent in ((False, True) if f.transparent else (False,))]


def first_frame_format(path, decoder=None) -> str:
    with av.open(str(path)) as container:
        stream = container.streams.video[0]
        if decoder is None:
            return next(container.decode(stream)).format.name
        context = av.CodecContext.create(decoder, "r")
        return next(frame for packet in container.demux(stream) for frame in context.decode(packet)).format.name


@pytest.mark.parametrize("name, codec, transparent", CASES)
def test_each_format_decodes_as_the_table_says(tmp_path, monkeypatch, name, codec, transparent):
    monkeypatch.chdir(tmp_path)
    spec = FORMATS[name]
    args = ["render", "single_bounce", "--seconds", "0.1", "--fps", "20", "--size", "160x90", "--no-progress",
            "--format", name, "-o", "out"] + (["--codec", codec] if name == "mp4" else [])   # --codec is mp4's
    assert main(args + (["-t"] if transparent else [])) == 0
    path = tmp_path / "renders" / "single_bounce" / f"out{spec.extension}"
    if name == "png":
        path = sorted(path.iterdir())[0]
    decoder = spec.alpha_decoder if transparent else None
    assert first_frame_format(path, decoder) == spec.decodes[transparent]
