"""The `ccd` method: exact event-driven motion between frames (continuous collision detection).

events.py    the event loop: jump from collision to collision, sample at frame times
stepper.py   runs it a block of frames at a time for the engine
The times of impact it predicts with are in geometry/toi.py.
"""
from .events import CCDResult, simulate_events
from .stepper import CCDStepper

__all__ = ["CCDResult", "CCDStepper", "simulate_events"]
