"""The player: view (world to pixels) -> raster (OpenCV) -> player (panels, HUD, overlays)
-> video (the frame loop into a writer). It draws trajectories; it never simulates."""
from .player import Chapter, FrameState, PanelSource

__all__ = ["Chapter", "FrameState", "PanelSource"]
