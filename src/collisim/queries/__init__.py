"""Queries on a world that do not move it: ray casts (rays.py; the compiled loop in cast.py)."""
from .rays import KIND_NAMES, RayHit, RayHits, raycast, raycast_many

__all__ = ["KIND_NAMES", "RayHit", "RayHits", "raycast", "raycast_many"]
