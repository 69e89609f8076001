"""Benchmarks: timing collisim's building blocks against reference libraries."""
