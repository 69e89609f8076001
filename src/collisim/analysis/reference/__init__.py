"""Outside references to check collisim against.

pymunk_mirror   the same World stepped by pymunk (Chipmunk2D), recorded as a Trajectory
"""
from .pymunk_mirror import simulate_pymunk

__all__ = ["simulate_pymunk"]
