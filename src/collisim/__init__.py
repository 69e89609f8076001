"""collisim: a frame-recording animation renderer for collision simulations.

    scene file -> Scene -> World (bodies, statics) -> engine (discrete or ccd) -> Trajectory
               -> player (raster, overlays) -> writer (PyAV) -> renders/<scene>.mp4
"""
from .core.compiling import name_entries_by_key, plain_constants, stamp_with_package

plain_constants()      # before any kernel is typed: one compile per argument types (compiling.py)
stamp_with_package()   # before any kernel is cached: a change to any source compiles them again
name_entries_by_key()  # and processes compiling at once never mix up each other's entries

from .engine import simulate, stream  # noqa: E402
from .model import Events, Panel, RenderSettings, Scene, Trajectory, World, load_trajectory
from .model.scenefile import load_scene
from .notebook import show
from .pipeline import render
from .queries import RayHit, RayHits, contacts, raycast, raycast_many
from .statics.collision_map import CollisionMap

__version__ = "0.1.0"
__all__ = ["World", "Scene", "Panel", "RenderSettings", "Trajectory", "Events", "simulate", "stream", "render",
           "load_scene", "load_trajectory", "contacts", "show", "CollisionMap",
           "raycast", "raycast_many", "RayHit", "RayHits"]
