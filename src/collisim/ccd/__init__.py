"""Continuous collision detection: exact times of impact and event-driven simulation.

toi.py      time of impact of a moving circle with a wall, a circle or a segment
events.py   method `ccd`: jump from collision to collision, sample at frame times
"""
from .events import CCDResult, simulate_events
from .toi import time_to_pair, time_to_point, time_to_segment, time_to_wall

__all__ = ["CCDResult", "simulate_events", "time_to_wall", "time_to_pair", "time_to_point", "time_to_segment"]
