"""The engine: step a World at a fixed frame rate and record a Trajectory.

discrete: integrate -> broad phase -> narrow phase -> response -> walls, k substeps a frame.
ccd:      exact event-driven motion between frames (collisim.ccd).
"""
from .simulate import simulate, stream

__all__ = ["simulate", "stream"]
