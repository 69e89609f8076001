"""Output: video writers behind one interface (writers.py). Trajectory files are written by
Trajectory.save and read by collisim.load_trajectory (model/trajectory.py)."""
from .writers import WRITERS, open_writer, write_png

__all__ = ["WRITERS", "open_writer", "write_png"]
