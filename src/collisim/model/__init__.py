"""What a simulation is about: the world (bodies and statics), the scene, the trajectory."""
from .scene import Panel, RenderSettings, Scene
from .trajectory import Events, Trajectory, load_trajectory
from .world import World

__all__ = ["World", "Scene", "Panel", "RenderSettings", "Trajectory", "Events", "load_trajectory"]
