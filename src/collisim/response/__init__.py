"""Collision response: impulses for the contacts the narrow phase found, overlap removal, and
the bounce off the walls and segments. impulse.py holds the two formulas every path uses."""
