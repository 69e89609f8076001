"""A PNG sequence: one file per frame, NAME_0000.png, NAME_0001.png, … in a folder of its own
(RGBA when transparent). The folder is written under a hidden temporary name beside it and
renamed when complete, like every other output."""
from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path

import cv2
import numpy as np

from ..core.files import plain_permissions
from .base import VideoWriter

PNG_LEVEL = 1   # zlib level: fast; flat animation compresses well anyway


def check_sequence_folder(path: Path) -> None:
    """ValueError unless `path` may become a sequence folder: new, empty, or an earlier PNG
    sequence (only .png files), which the new one replaces."""
    if not path.exists():
        return
    if not path.is_dir():
        raise ValueError(f"cannot write a PNG sequence to {path}: it is a file")
    others = [p.name for p in path.iterdir() if p.suffix.lower() != ".png" or not p.is_file()]
    if others:
        raise ValueError(f"cannot write a PNG sequence to {path}: the folder holds other files ({others[0]}); "
                         f"end --out with / to write the sequence into a new folder inside it")


class PngSequenceWriter(VideoWriter):
    """One PNG per frame in the folder `path`, named after `name`."""

    codec, alpha = "png", True

    def _make_temporary(self) -> Path:
        name = tempfile.mkdtemp(dir=self.path.parent, prefix=f".{self.path.name}-")
        plain_permissions(name)
        return Path(name)

    def _open(self) -> None:
        digits = max(4, len(str(max((self.expected_frames or 1) - 1, 0))))
        self._pattern = f"{self.name}_{{:0{digits}d}}.png"

    def _encode(self, bgr: np.ndarray) -> None:
        image = self._bgra(bgr) if self.transparent else bgr
        ok, data = cv2.imencode(".png", image, [cv2.IMWRITE_PNG_COMPRESSION, PNG_LEVEL])
        if not ok:
            raise ValueError(f"could not encode PNG frame {self._encoded}")
        (self.temporary / self._pattern.format(self._encoded)).write_bytes(data.tobytes())
        self._encoded += 1

    def _close(self, flush: bool) -> None:
        pass

    def _publish(self) -> None:
        """Rename the finished folder into place; an earlier sequence there is moved aside first
        (a folder cannot be renamed over a non-empty one) and removed afterwards."""
        old = None
        if self.path.exists():
            check_sequence_folder(self.path)
            old = Path(tempfile.mkdtemp(dir=self.path.parent, prefix=f".{self.path.name}-old-"))
            os.replace(self.path, old / "sequence")
        try:
            os.replace(self.temporary, self.path)
        except BaseException:
            if old is not None:
                os.replace(old / "sequence", self.path)
            raise
        finally:
            if old is not None:
                shutil.rmtree(old, ignore_errors=True)

    def _discard(self) -> None:
        shutil.rmtree(self.temporary, ignore_errors=True)
