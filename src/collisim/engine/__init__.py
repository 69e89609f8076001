"""The engine: step a World at a fixed frame rate and record a Trajectory.

discrete: integrate -> broad phase -> narrow phase -> response -> statics -> settle, k substeps
          a frame, one compiled loop per block of frames (discrete.py).
ccd:      exact event-driven motion between frames (ccd/).
"""
from .simulate import METHODS, concatenate, simulate, stream

__all__ = ["METHODS", "simulate", "stream", "concatenate"]
