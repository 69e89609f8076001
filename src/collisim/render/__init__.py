"""Drawing and encoding: view (world to pixels) -> raster (OpenCV) -> encoder (PyAV)."""
from .video import render

__all__ = ["render"]
