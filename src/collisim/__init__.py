"""collisim: a frame-recording animation renderer for collision simulations.

    scene file -> Scene -> World (arrays) -> simulate (discrete or ccd) -> Trajectory
               -> raster (OpenCV) -> encoder (PyAV) -> renders/<scene>.mp4
"""
from .engine import simulate, stream
from .render import render
from .scene import Panel, RenderSettings, Scene, load_scene
from .trajectory import Events, Trajectory
from .world import World

__version__ = "0.1.0"
__all__ = ["World", "Scene", "Panel", "RenderSettings", "Trajectory", "Events",
           "simulate", "stream", "render", "load_scene"]
