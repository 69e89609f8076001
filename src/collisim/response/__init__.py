"""Collision response: new velocities for the contacts the narrow phase found."""
