"""Measuring runs: metrics, the compare table, pymunk as the reference, the benchmarks."""
