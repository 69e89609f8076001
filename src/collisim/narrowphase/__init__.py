"""Narrow phase: exact tests on the candidate pairs the broad phase reports."""
