"""Queries on a world that do not move it: ray casts (rays.py; the compiled loop in cast.py) and the
contacts where the bodies stand (contacts.py)."""
from .contacts import contacts
from .rays import KIND_NAMES, RayHit, RayHits, raycast, raycast_many

__all__ = ["contacts", "KIND_NAMES", "RayHit", "RayHits", "raycast", "raycast_many"]
