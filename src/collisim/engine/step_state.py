"""What the discrete step holds (engine/discrete.py): the bodies, the statics and how contacts
respond, the contacts kept from block to block, and the step's per-body arrays."""
from collections import namedtuple

import numpy as np

from .fast_polygons import new_fast
from .hierarchy import level_scratch

ITERATIONS = 20   # sweeps of the contact solver per step (response/solver.py)

Bodies = namedtuple("Bodies", ["shapes", "positions", "velocities", "angles", "angular_velocities",
                               "accelerations", "radii", "masses", "inertias", "vertex_start", "body_vertices"])
Statics = namedtuple("Statics", ["box", "segments", "index", "map", "restitution", "rest_speed", "iterations",
                                 "friction", "volumes", "pulled", "keep", "soft", "rigid"],
                     defaults=(0.0, ITERATIONS, 0.0, None, None, 1.0, None, True))
Statics.__doc__ = """What bodies meet besides each other: box (4,), segments (m, 4) and their index, the
collision map's field (index and map None when the world has none: see statics_paths.py); and
how contacts respond: restitution e, the rest speed below which a contact rests instead of
bouncing, the solver's sweeps per step, and the friction coefficient; keep: the fraction of its
velocity a body keeps over a step (World.damping ** dt, 1 without damping); volumes True for a world
with polygons, whose frames count the bounding-volume funnel (narrowphase/hierarchy.py) and
whose contact phases compile the polygon paths (narrowphase/manifold.py), else None; pulled True
where a body has an acceleration, else None: with nothing pulling the hold (response/hold.py)
holds nothing, and is not compiled; soft True and rigid None where the soft step holds the
contacts (response/solve.py), soft None and rigid True where the rigid solve does: numba leaves
out a branch on `is None` only for an argument typed None, so each solver has its flag."""
Contacts = namedtuple("Contacts", ["found", "rows", "count", "pairs", "touching"])
Contacts.__doc__ = """The contacts the next step starts from, kept from block to block (finding them again at
each block's start cost a whole broad and narrow phase: a block is one frame at a million
bodies): found and rows (response/rows.py, grown as needed), the rows' count (-1 before the
first block: not found yet), the candidate pairs (k, 2) and which of them touch (k,) (empty
when not known: a world asleep then finds them again, by the exact test, at every block)."""
Work = namedtuple("Work", ["lo", "hi", "margin", "push", "shift", "push_turn", "shift_turn", "vertices",
                           "inverse_masses", "inverse_inertias", "moved", "fast", "levels", "recorded"])
Work.__doc__ = """The step's per-body arrays, made once a run (made at every block, they were a tenth of a
gigabyte a frame at a million bodies): the bounding boxes lo, hi (n, 2) and margins (n,) of
the contact phases; the solver's push, shift (n, 2) and their turns (n,) (response/solver.py);
the polygons' placed vertices; 1/m and 1/I (the solver multiplies); moved (n,) bool, all False
between steps (add_contact_motion); fast: the fast polygons' (fast_polygons.py); levels:
record_levels' scratch (hierarchy.level_scratch); recorded (5,) int64: the last frame recorded's
funnel counts (out.hierarchy's row) and whether every body was still at it (1, else 0), so that a
block of a world asleep copies them rather than count them again."""


def new_work(bodies) -> Work:
    n = len(bodies.positions)
    return Work(np.empty((n, 2)), np.empty((n, 2)), np.empty(n), np.zeros((n, 2)), np.zeros((n, 2)), np.zeros(n),
                np.zeros(n), np.empty_like(bodies.body_vertices), 1.0 / bodies.masses, 1.0 / bodies.inertias,
                np.zeros(n, np.bool_), new_fast(n), level_scratch(bodies), np.zeros(5, np.int64))
