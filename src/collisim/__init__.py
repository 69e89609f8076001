"""collisim: a frame-recording animation renderer for collision simulations.

    scene file -> Scene -> World (bodies, statics) -> engine (discrete or ccd) -> Trajectory
               -> player (raster, overlays) -> writer (PyAV) -> renders/<scene>.mp4
"""
from .core.compiling import refuse_arrays_from_kernels, save_one_process_at_a_time, use_cache_folder

use_cache_folder()                # before any kernel is defined: kept in a folder of these sources' own
save_one_process_at_a_time()    # and never saved there by two processes at once (core/compiling.py)
refuse_arrays_from_kernels()    # a kernel returning an array fails as it compiles, not later

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
