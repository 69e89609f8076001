"""Discrete collision detection: step, then look for contacts at the end of the step.

One step of dt is the pipeline below, each phase timed into the profile (engine/profile.py):

    integrate     p += v·dt + ½·a·dt², v += a·dt, θ += ω·dt
    broad         candidate pairs from the bodies' bounding boxes (any of the five broad phases)
    narrow        keep the candidates that really touch (narrowphase/registry.py)
    response      impulses, then overlap removal, in sorted pair order (response/pairs.py)
    statics       segments near each body (statics/segment_index.py), the collision map
                  (each step's move marched through its distance field), then the box walls
    settle        a wall bounce may push a body back into its partner: separate this step's
                  contacts again and keep every body in the box and out of the map
                  (positions only)
    record        the frame's state into the trajectory

A frame is k substeps of dt/k. The whole block of frames runs as one compiled call (a Python
call per phase would cost more than the work at a thousand bodies); with fewer than two
bodies no pair phase runs.
"""
from __future__ import annotations

from collections import namedtuple

import numpy as np
from numba import njit

from ..broadphase.step import AUTO, candidate_pairs, choose, step_state
from ..geometry.box import centre_range, clamp_into_box
from ..model.kinds import MAP, PAIR, SEGMENT, WALL
from ..narrowphase.registry import touching_pairs
from ..narrowphase.statics import segment_contacts
from ..response.map import bounce_off_map, push_out
from ..response.pairs import resolve_pairs, separate_pairs
from ..response.statics import bounce_between_walls, bounce_off_segment
from ..statics.map_field import has_map, no_map_field
from ..statics.segment_index import build_segment_index
from .eventlog import append, log_events, new_log, with_room
from .integrate import integrate
from .profile import Profile, cycles

INTEGRATE, BROAD, NARROW, RESPONSE, STATICS, SETTLE, RECORD, TOTAL = range(8)

Bodies = namedtuple("Bodies", ["shapes", "positions", "velocities", "angles", "angular_velocities",
                               "accelerations", "radii", "masses"])
Statics = namedtuple("Statics", ["box", "segments", "index", "map", "restitution"])
Frames = namedtuple("Frames", ["positions", "velocities", "angles", "angular_velocities", "collisions",
                               "candidates", "approximate"])
Frames.__doc__ = """A block of frames: positions, velocities (f, n, 2); angles, angular_velocities (f, n);
collisions (f, 3) wall, pair, segment in the interval ending at each frame; candidates (f,);
approximate (f,) bool: frames the method could not finish exactly (see Trajectory)."""


@njit(cache=True)
def _lap(phase_cycles, phase, since):
    now = cycles()
    phase_cycles[phase] += now - since
    return now


@njit(cache=True)
def _bounds(bodies, lo, hi):
    """Each body's bounding box (n, 2) lo, hi from its shape (circles: centre ± radius)."""
    for i in range(bodies.positions.shape[0]):
        for axis in range(2):
            lo[i, axis] = bodies.positions[i, axis] - bodies.radii[i]
            hi[i, axis] = bodies.positions[i, axis] + bodies.radii[i]


@njit(cache=True)
def sort_pairs(pairs, n):
    """Pairs (k, 2) with i < j, each once, in lexicographic (i, j) order: the canonical order
    in which the response treats contacts, whichever broad phase found them."""
    return pairs[np.argsort(pairs[:, 0] * n + pairs[:, 1])]


@njit(cache=True)
def _pair_phases(bodies, statics, broad, lo, hi, log, now, frame_collisions, phase_cycles, t):
    """broad, narrow and response: returns (contacts, candidates, log, t)."""
    b = bodies
    _bounds(b, lo, hi)
    pairs = candidate_pairs(broad, lo, hi)
    t = _lap(phase_cycles, BROAD, t)
    contacts = sort_pairs(touching_pairs(b.shapes, b.positions, b.radii, pairs), lo.shape[0])
    t = _lap(phase_cycles, NARROW, t)
    impulse, point = np.empty(contacts.shape[0]), np.empty((contacts.shape[0], 2))
    frame_collisions[PAIR] += resolve_pairs(b.shapes, b.positions, b.velocities, b.masses, b.radii, contacts,
                                            contacts.shape[0], statics.restitution, impulse, point)
    log = with_room(log, contacts.shape[0])
    for c in range(contacts.shape[0]):
        if impulse[c] > 0.0:
            append(log, now, PAIR, contacts[c, 0], contacts[c, 1], impulse[c], point[c, 0], point[c, 1])
    t = _lap(phase_cycles, RESPONSE, t)
    return contacts, pairs.shape[0], log, t


@njit(cache=True)
def statics_scratch(n, m):
    """Buffers for statics_phase: segment contacts (room for one a body; grown when a step has
    more), near segments (m,), and the positions (n, 2) at the start of the step (the map
    marches each step's move from there)."""
    return np.empty((n + 16, 2), np.int64), np.empty(max(m, 1), np.int64), np.empty((n, 2))


@njit(cache=True)
def statics_phase(bodies, statics, scratch, dt, log, now, frame_collisions):
    """Segments, then walls, in place; collisions added to frame_collisions (3,: wall, pair,
    segment) and log. scratch from statics_scratch. Returns the log."""
    b, s = bodies, statics
    if s.segments.shape[0] > 0:
        found, count = segment_contacts(b.positions, b.radii, s.segments, s.index, scratch[0], scratch[1])
        log = with_room(log, count)
        for c in range(count):
            i, k = found[c, 0], found[c, 1]
            impulse, x, y = bounce_off_segment(b.positions, b.velocities, b.radii, b.masses, s.segments, i, k,
                                               s.restitution)
            if impulse > 0.0:
                append(log, now, SEGMENT, i, k, impulse, x, y)
                frame_collisions[SEGMENT] += 1
    if has_map(s.map):
        log = map_phase(b, s, scratch[2], dt, log, now, frame_collisions)
    log = with_room(log, 4 * b.positions.shape[0])  # at most one event per body and wall
    for i in range(b.positions.shape[0]):
        for axis in range(2):
            low, high = centre_range(s.box, axis, b.radii[i])
            if low <= b.positions[i, axis] <= high:
                continue  # the extreme points are inside: no wall touched on this axis
            low_bounces, high_bounces, low_impulse, high_impulse = bounce_between_walls(
                b.positions, b.velocities, b.accelerations, b.radii, b.masses, s.box, s.restitution, i, axis)
            if low_bounces > 0:
                _log_wall(log, now, b.positions, s.box, i, axis, 0, low_impulse)
            if high_bounces > 0:
                _log_wall(log, now, b.positions, s.box, i, axis, 1, high_impulse)
            frame_collisions[WALL] += low_bounces + high_bounces
    return log


@njit(cache=True)
def map_phase(bodies, statics, start, dt, log, now, frame_collisions):
    """Every body's move this step of dt (from start (n, 2)) against the collision map; bounces are
    counted with the segments' (frame_collisions[SEGMENT]) and logged as MAP events."""
    b = bodies
    log = with_room(log, b.positions.shape[0])
    for i in range(b.positions.shape[0]):
        impulse, x, y, bounces = bounce_off_map(statics.map, start, b.positions, b.velocities, b.accelerations,
                                                b.radii, b.masses, statics.restitution, dt, i)
        if bounces > 0:
            append(log, now, MAP, i, -1, impulse, x, y)
            frame_collisions[SEGMENT] += bounces
    return log


@njit(cache=True)
def _log_wall(log, now, positions, box, i, axis, side, impulse):
    """Log body i's bounce off wall 2·axis + side, at the wall beside the body."""
    on_wall, along = box[axis + 2 * side], positions[i, 1 - axis]
    x, y = (on_wall, along) if axis == 0 else (along, on_wall)
    append(log, now, WALL, i, 2 * axis + side, impulse, x, y)


@njit(cache=True)
def run_frames(bodies, statics, broad, dt, substeps, step_count, out, log, phase_cycles):
    """Advance bodies in place by out's frame count, each frame `substeps` steps of dt, filling
    out (Frames) and appending every collision to log. phase_cycles (8,) int64 receives the
    cycles per phase and their total. Returns the log."""
    start = cycles()
    b, s = bodies, statics
    n = b.positions.shape[0]
    lo, hi = np.empty((n, 2)), np.empty((n, 2))
    scratch = statics_scratch(n, s.segments.shape[0])
    t = start
    for frame in range(out.positions.shape[0]):
        frame_collisions = out.collisions[frame]
        for _ in range(substeps):
            step_count += 1
            now = step_count * dt
            t = cycles()
            if has_map(s.map):
                scratch[2][:] = b.positions
            integrate(b.positions, b.velocities, b.accelerations, b.angles, b.angular_velocities, dt)
            t = _lap(phase_cycles, INTEGRATE, t)
            contacts = np.empty((0, 2), np.intp)
            if n >= 2:
                contacts, candidates, log, t = _pair_phases(b, s, broad, lo, hi, log, now, frame_collisions, phase_cycles, t)
                out.candidates[frame] = candidates
            log = statics_phase(b, s, scratch, dt, log, now, frame_collisions)
            t = _lap(phase_cycles, STATICS, t)
            if contacts.shape[0] > 0:
                separate_pairs(b.shapes, b.positions, b.masses, b.radii, contacts, contacts.shape[0])
                clamp_into_box(b.positions, b.radii, s.box)
                if has_map(s.map):
                    for i in range(n):
                        push_out(s.map, b.positions, b.radii[i], i)
                t = _lap(phase_cycles, SETTLE, t)
        out.positions[frame] = b.positions
        out.velocities[frame] = b.velocities
        if out.angles.shape[1] == n:  # bodies that turn (see new_frames)
            out.angles[frame] = b.angles
            out.angular_velocities[frame] = b.angular_velocities
        t = _lap(phase_cycles, RECORD, t)
    phase_cycles[TOTAL] += cycles() - start
    return log


def new_frames(count: int, n: int, turning: bool = True) -> Frames:
    """Room for `count` frames of n bodies. Without `turning` the angle arrays have no columns:
    bodies that never turn keep their angles, and storing them every frame would cost as much
    memory traffic as the positions (see constant_angles)."""
    columns = n if turning else 0
    return Frames(np.empty((count, n, 2)), np.empty((count, n, 2)), np.empty((count, columns)),
                  np.empty((count, columns)), np.zeros((count, 3), np.int64), np.zeros(count, np.int64),
                  np.zeros(count, np.bool_))


def constant_angles(frames: Frames, angles, angular_velocities) -> Frames:
    """Frames whose angle arrays are read-only views repeating the bodies' constant angles and
    angular velocities (no memory per frame)."""
    count = len(frames.positions)
    return frames._replace(angles=np.broadcast_to(angles, (count, len(angles))),
                           angular_velocities=np.broadcast_to(angular_velocities, (count, len(angles))))


class DiscreteStepper:
    """Advances a copy of a world, a block of frames at a time."""

    def __init__(self, world, fps: float, substeps: int = 1, broadphase: str = "auto",
                 profile: Profile | None = None):
        w = world
        self.bodies = Bodies(w.shapes, w.positions.copy(), w.velocities.copy(), w.angles.copy(),
                             w.angular_velocities.copy(), w.accelerations, w.radii, w.masses)
        index = build_segment_index(w.segments, w.box)
        field = no_map_field() if w.map is None else w.map.field
        self.statics = Statics(w.box, w.segments, index, field, float(w.restitution))
        self.broad = step_state(broadphase, world)
        chosen = f"{choose(world)} (auto)" if broadphase == AUTO else broadphase
        self.broadphase = chosen if w.n >= 2 else ""
        self.dt = 1.0 / fps / substeps
        self.substeps = int(substeps)
        self.profile = profile or Profile()
        self.step_count = 0
        self.warnings = []

    def run(self, count: int):
        """Advance `count` frames: (Frames, Events)."""
        b = self.bodies
        turning = bool(np.any(b.angular_velocities != 0.0))  # nothing exerts torque yet: ω stays as given
        out = new_frames(count, len(b.positions), turning)
        log = self.profile.timed(lambda phase_cycles: run_frames(
            b, self.statics, self.broad, self.dt, self.substeps, self.step_count, out, new_log(64), phase_cycles))
        self.step_count += count * self.substeps
        if not turning:
            out = constant_angles(out, b.angles.copy(), b.angular_velocities.copy())
        return out, log_events(log)
