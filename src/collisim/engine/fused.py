"""The discrete step as compiled code from end to end, a block of frames per call.

The phased pipeline in discrete.py calls one kernel per phase from Python and times each
phase; at a thousand particles those calls cost more than the work. Here the same kernels
(integrate, grid broad phase, narrow phase, response, walls, settle) run in the same order inside
one numba function for a whole block of frames, on a uniform grid laid once over the world's
box (particles never leave it). Contacts are sorted into the same (i, j) order as the phased
pipeline, and events are recorded in the same form, so both give identical bytes. The engine
uses it for the grid broad phase when no barriers are present.
"""
from __future__ import annotations

import numpy as np
from numba import njit

from ..broadphase.grid import bin_boxes, grid_pairs
from ..narrowphase.circles import touching_pairs
from ..response.elastic import resolve_contacts, separate_contacts
from ..trajectory import PAIR, WALL, Events
from .block import FrameBlock
from .integrate import integrate
from .walls import clamp_into_box, collide_walls


def box_grid(box, radii) -> tuple:
    """Cell size and shape of a fixed grid over the box: cells twice the median diameter,
    widened so there are at most about 4n cells."""
    width, height = box[2] - box[0], box[3] - box[1]
    cell = max(4.0 * float(np.median(radii)), np.sqrt(width * height / (4 * len(radii))))
    return cell, (int(width // cell) + 1, int(height // cell) + 1)


class FusedGrid:
    """Runs blocks of frames of a world through `run_frames`."""

    def __init__(self, world, dt: float, substeps: int):
        self.world, self.dt, self.substeps = world, dt, substeps
        self.cell, (self.nx, self.ny) = box_grid(world.box, world.radii)

    def run(self, positions, velocities, step_count: int, count: int) -> FrameBlock:
        """Advance positions, velocities (n, 2) in place by count frames."""
        w = self.world
        out = run_frames(positions, velocities, w.accelerations, w.radii, w.masses, w.box, w.restitution,
                         self.dt, self.substeps, step_count, count, self.cell, self.nx, self.ny)
        frame_positions, frame_velocities, hits, candidates, k, time, kind, first, second, impulse, point = out
        events = Events(time[:k], kind[:k], first[:k], second[:k], impulse[:k], point[:k])
        return FrameBlock(frame_positions, frame_velocities, hits, candidates, Events.concatenate([events]))


@njit(cache=True)
def sort_pairs(pairs, n):
    """Pairs (k, 2) in lexicographic (i, j) order (keys i·n + j are unique)."""
    keys = pairs[:, 0] * n + pairs[:, 1]
    return pairs[np.argsort(keys)]


@njit(cache=True)
def _grown(array, size):
    """array with room for at least `size` rows, doubling as needed."""
    if size <= array.shape[0]:
        return array
    bigger = np.empty((max(size, 2 * array.shape[0]),) + array.shape[1:], array.dtype)
    bigger[:array.shape[0]] = array
    return bigger


@njit(cache=True)
def run_frames(positions, velocities, accelerations, radii, masses, box, restitution, dt, substeps,
               step_count, frames, cell_size, nx, ny):
    """Advance `frames` frames of `substeps` steps of dt, in place.

    Returns per-frame positions and velocities (frames, n, 2), hits (frames, 3), candidates
    (frames,), then the event count k and event arrays time, kind, i, j, impulse, point
    (only the first k rows are valid).
    """
    n = positions.shape[0]
    out_positions, out_velocities = np.empty((frames, n, 2)), np.empty((frames, n, 2))
    hits, candidates = np.zeros((frames, 3), np.int64), np.zeros(frames, np.int64)
    wall_particle, wall_side = np.empty(4 * n, np.intp), np.empty(4 * n, np.intp)
    wall_impulse, wall_point = np.empty(4 * n), np.empty((4 * n, 2))
    time, kind = np.empty(4 * n), np.empty(4 * n, np.int8)
    first, second = np.empty(4 * n, np.intp), np.empty(4 * n, np.intp)
    impulse, point = np.empty(4 * n), np.empty((4 * n, 2))
    k = 0
    lo, hi = np.empty((n, 2)), np.empty((n, 2))
    origin = box[:2].copy()
    for frame in range(frames):
        for _ in range(substeps):
            step_count += 1
            now = step_count * dt
            integrate(positions, velocities, accelerations, dt)
            for i in range(n):
                for axis in range(2):
                    lo[i, axis] = positions[i, axis] - radii[i]
                    hi[i, axis] = positions[i, axis] + radii[i]
            cell_start, cell_boxes = bin_boxes(lo, hi, origin, 1.0 / cell_size, nx, ny)
            pairs = grid_pairs(lo, hi, origin, 1.0 / cell_size, nx, ny, cell_start, cell_boxes)
            candidates[frame] = pairs.shape[0]
            contacts = sort_pairs(touching_pairs(positions, radii, pairs), n)
            pair_impulse, pair_point = np.empty(contacts.shape[0]), np.empty((contacts.shape[0], 2))
            hits[frame, 1] += resolve_contacts(positions, velocities, masses, radii, contacts, restitution,
                                               pair_impulse, pair_point)
            walls, wall_hits = collide_walls(positions, velocities, accelerations, radii, masses, box, restitution,
                                             wall_particle, wall_side, wall_impulse, wall_point)
            hits[frame, 0] += wall_hits
            if contacts.shape[0] > 0:
                separate_contacts(positions, masses, radii, contacts)
                clamp_into_box(positions, radii, box)
            # record this step's events: pairs that got an impulse, then walls
            need = k + contacts.shape[0] + walls
            time, kind, first, second = _grown(time, need), _grown(kind, need), _grown(first, need), _grown(second, need)
            impulse, point = _grown(impulse, need), _grown(point, need)
            for c in range(contacts.shape[0]):
                if pair_impulse[c] > 0.0:
                    time[k], kind[k], first[k], second[k] = now, PAIR, contacts[c, 0], contacts[c, 1]
                    impulse[k], point[k] = pair_impulse[c], pair_point[c]
                    k += 1
            for e in range(walls):
                time[k], kind[k], first[k], second[k] = now, WALL, wall_particle[e], wall_side[e]
                impulse[k], point[k] = wall_impulse[e], wall_point[e]
                k += 1
        out_positions[frame] = positions
        out_velocities[frame] = velocities
    return out_positions, out_velocities, hits, candidates, k, time, kind, first, second, impulse, point
