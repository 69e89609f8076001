"""Outside references to check collisim against, and to time it against.

pymunk_mirror   the same World stepped by pymunk (Chipmunk2D), recorded as a Trajectory, with
                callbacks on every contact: for checking physics, never for timing
plain_pymunk    the Space a user would build for the World (defaults, no callbacks): the speed
                baseline of the benchmarks
bodies          the World's circles and polygons as pymunk bodies, and their state read back
                (shared by both)
"""
from .plain_pymunk import PlainPymunk, simulate_plain_pymunk, time_plain_pymunk
from .pymunk_mirror import simulate_pymunk

__all__ = ["PlainPymunk", "simulate_plain_pymunk", "simulate_pymunk", "time_plain_pymunk"]
