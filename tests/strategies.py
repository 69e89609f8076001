"""Hypothesis strategies shared by the broad-phase tests."""
import numpy as np
from hypothesis import strategies as st

# Small integers make exact ties (touching boxes, rays through edges and corners) common;
# floats cover the rest.
coordinate = st.one_of(st.integers(-20, 20).map(float),
                       st.floats(-100, 100, allow_nan=False, allow_infinity=False))
extent = st.one_of(st.integers(0, 6).map(float), st.floats(0, 30, allow_nan=False))


@st.composite
def box_arrays(draw):
    """Up to 40 boxes as lo, hi: (n, 2) each."""
    rows = draw(st.lists(st.tuples(coordinate, coordinate, extent, extent), max_size=40))
    table = np.array(rows, float).reshape(-1, 4)
    lo = table[:, :2]
    return lo, lo + table[:, 2:]


# Options each broad phase is tried with.
OPTIONS = {
    "brute": st.just({}),
    "sweep_prune": st.just({}),
    "grid": st.one_of(st.just({}), st.builds(dict, cell_size=st.floats(0.5, 50))),
    "kdtree": st.builds(dict, leaf_size=st.integers(1, 6), max_depth=st.integers(0, 12)),
    "bvh": st.builds(dict, leaf_size=st.integers(1, 6)),
    "cells": st.just({}),
}
