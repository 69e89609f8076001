import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]


def run_cli(*args, cwd=None, timeout=300):
    """Run `collisim ARGS` in a subprocess, as a user would."""
    return subprocess.run([sys.executable, "-m", "collisim", *map(str, args)], cwd=cwd or ROOT,
                          capture_output=True, text=True, timeout=timeout)


@pytest.fixture
def cli():
    return run_cli


def decode_video(path):
    """Decode every frame: (count, width, height, average rate, codec name, pixel format)."""
    import av
    with av.open(str(path)) as container:
        stream = container.streams.video[0]
        count = sum(1 for _ in container.decode(stream))
        return count, stream.width, stream.height, stream.average_rate, stream.codec_context.name, \
            stream.codec_context.pix_fmt


@pytest.fixture
def rng():
    return np.random.default_rng(12345)
