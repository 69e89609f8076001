"""The bottom layer: checks, kinds, arrays, files, how kernels compile, and geometry on plain
numbers and arrays. It imports nothing of collisim above it."""
