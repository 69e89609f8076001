"""Narrow phase: exact contact tests on the candidates the broad phase reports.

registry.py holds the table from a pair of shape kinds to its contact function (as Box2D's
shape-pair table does); circles.py and statics.py hold the functions.
"""
from .registry import SHAPE_PAIRS, STATIC_PAIRS

__all__ = ["SHAPE_PAIRS", "STATIC_PAIRS"]
