import os
import signal
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="session", autouse=True)
def own_text_cache(tmp_path_factory):
    """The suite keeps its typeset text (render/textcache.py) in a folder of its own, not the
    user's, for the CLI's subprocesses too."""
    before = os.environ.get("COLLISIM_CACHE_DIR")
    os.environ["COLLISIM_CACHE_DIR"] = str(tmp_path_factory.mktemp("collisim-cache"))
    yield
    if before is None:
        del os.environ["COLLISIM_CACHE_DIR"]
    else:
        os.environ["COLLISIM_CACHE_DIR"] = before


def run_cli(*args, cwd=None, timeout=300):
    """Run `collisim ARGS` in a subprocess, as a user would."""
    return subprocess.run([sys.executable, "-m", "collisim", *map(str, args)], cwd=cwd or ROOT,
                          capture_output=True, text=True, timeout=timeout)


def as_a_fresh_process():
    """A child's SIGINT as a shell gives it: handled by default and not blocked. A test worker may
    have it ignored or blocked at the system level (a library in it may have set that), and a child
    inherits both: Python then leaves Ctrl-C ignored or pending, and collisim rightly so. Pass as
    `preexec_fn` to a child that is sent SIGINT."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, [signal.SIGINT])


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


def statics_step(positions, velocities, radii, masses, box, segments=None, restitution=1.0, accelerations=None):
    """One statics phase of the discrete step (segments, then walls) on raw arrays, in place:
    returns (collisions (3,) wall, pair, segment, Events)."""
    from collisim.engine.statics_paths import statics_phase, statics_scratch
    from collisim.engine.step_state import Bodies, Statics
    from collisim.engine.eventlog import log_events, new_log
    from collisim.statics import build_segment_index
    n = len(positions)
    segments = np.zeros((0, 4)) if segments is None else np.asarray(segments, float).reshape(-1, 4)
    box = np.asarray(box, float)
    accelerations = np.zeros((n, 2)) if accelerations is None else np.asarray(accelerations, float)
    masses, radii = np.asarray(masses, float), np.asarray(radii, float)
    bodies = Bodies(np.zeros(n, np.int8), positions, velocities, np.zeros(n), np.zeros(n), accelerations,
                    radii, masses, 0.5 * masses * radii ** 2, np.zeros(n + 1, np.int64), np.zeros((0, 2)))
    from collisim.statics.map_field import no_map_field
    statics = Statics(box, segments, build_segment_index(segments, box), no_map_field(), float(restitution))
    counts = np.zeros(3, np.int64)
    log = statics_phase(bodies, statics, statics_scratch(n, len(segments)), 1.0, new_log(4), 0.0, counts)
    return counts, log_events(log)


@pytest.fixture
def rng():
    return np.random.default_rng(12345)
