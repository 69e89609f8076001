"""What a stepper hands back for a run of frames."""
from typing import NamedTuple

import numpy as np

from ..trajectory import Events


class FrameBlock(NamedTuple):
    """count frames after the stepper's current one.

    positions, velocities: (count, n, 2)
    hits: (count, 3)       wall, pair and segment collisions in the interval ending at each frame
    candidates: (count,)   broad-phase candidate pairs of each frame's last step
    events: every collision of the block
    """
    positions: np.ndarray
    velocities: np.ndarray
    hits: np.ndarray
    candidates: np.ndarray
    events: Events
