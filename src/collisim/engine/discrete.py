"""Discrete collision detection: contacts found at the start of each step, solved, then the step.

One step of dt is the pipeline below, each phase timed into the profile (engine/profile.py):

    broad         candidate pairs from the bodies' bounding boxes grown by their speculative
                  margins (any of the five broad phases), from the state the step starts from
                  (found at the end of the step before, so a frame's candidates are its own)
    narrow        contact rows: pairs within their margins, bodies held by a wall
                  (response/rows.py)
    response      impacts (Newton's impulse), then the contact solver: warm-started sequential
                  impulses, split-impulse position correction (response/solver.py), held from
                  below where a heavy body rests on light ones (response/hold.py)
    integrate     p += v·dt + ½·a·dt², v += a·dt, θ += ω·dt, plus the solver's share; then
                  contacts that pressed come to rest (response)
    statics       a lone polygon faster than its size a step flown against the walls, each
                  met at its time of impact (fast_polygons.py); segments near each body
                  (statics/segment_index.py), the collision map (each step's move marched
                  through its distance field), then the box walls (a body the solver held
                  against a wall is kept on it, not bounced)
    settle        keep bodies out of the map (positions only)
    record        the frame's state into the trajectory, and how many of its pairs pass each
                  level of the bounding volumes (narrowphase/hierarchy.py; worlds with polygons)

A frame is k substeps of dt/k, and a block of frames one compiled call (a Python call per phase
would cost more than the work at a thousand bodies); with fewer than two bodies no pair phase runs.
Once every body sleeps (engine/islands.py) nothing can move or wake, and the rest of the block is
the sleepers' support, logged, and the record: as in Box2D, a world asleep costs nothing more.
"""
from __future__ import annotations

import numpy as np

from ..core.arrays import copy_rows
from ..broadphase.registry import AUTO, choose, step_state
from ..broadphase.step import candidate_pairs, sort_pairs
from ..core.compiling import compiled, kernel
from ..core.geometry.polygon import place_any_polygons
from ..core.kinds import CIRCLE, MAP, N_WALLS, PAIR, SEGMENT, SUPPORT, WALL, shapes_flag
from ..model.trajectory import Events
from .hierarchy import record_levels
from ..response.hold import held_note
from ..response.pair_rows import pair_manifolds
from ..response.rows import margin_of, margins, new_found, new_rows, rows_from, wall_manifolds, was_impact
from ..response.solve import flags_of, hold_contacts, rest_contacts, solver_of
from ..response.solver import add_contact_motion, collide
from ..response.warmstart import no_memory, recall, remember
from ..statics.segment_index import build_segment_index
from .cell_order import ORDER_FRAMES, events_in_world_numbers, in_world_numbers, keeps_cell_order, renumber
from .frames import Frames, constant_angles, new_frames, record_state, repeat_idle
from .idle import idle_block, timed_idle
from .eventlog import append, into_canonical_order, log_events, new_log, with_room
from .fast_polygons import (fast_note, fly_swept, keep_starts, mark_swept, note_outpaced, outpaced,
                            segment_reach)
from .islands import new_sleep
from .step_state import ITERATIONS, Bodies, Contacts, Statics, new_work
from .integrate import integrate
from .profile import Profile, cycles
from .sleep_paths import carry, doze, keep_touching, remember_sleepers, still, wake
from .statics_paths import (circle_map_rows, circle_segment_rows, keep_start, map_number, mark_held, may_turn,
                            polygon_segment_rows, settle_in_map, static_kind, statics_phase, statics_scratch)

# numpy integers: _lap(cycles, BROAD, t) compiles once, not once per phase (core/kinds.py says why)
INTEGRATE, BROAD, NARROW, RESPONSE, STATICS, SETTLE, SLEEP, RECORD, TOTAL = np.arange(9, dtype=np.int64)
@kernel
def _lap(phase_cycles, phase, since):
    now = cycles()
    phase_cycles[phase] += now - since
    return now


@kernel
def _margins_and_bounds(bodies, dt, margin, lo, hi):
    """Each body's speculative margin (n,) (response/rows.py: margins) and its bounding box
    (n, 2) lo, hi from its shape (circles: centre ± radius) grown by that margin, in one pass
    over the bodies (at a million bodies a pass costs about as much as all the contacts)."""
    b = bodies
    for i in range(b.positions.shape[0]):
        margin[i] = margin_of(b.velocities, b.angular_velocities, b.accelerations, b.radii, dt, i)
        reach = b.radii[i] + margin[i]
        for axis in range(2):
            lo[i, axis] = b.positions[i, axis] - reach
            hi[i, axis] = b.positions[i, axis] + reach


def bounding_boxes(world, positions, velocities, fps: float, substeps: int = 1):
    """The boxes (lo, hi) (n, 2) the discrete step's broad phase sees for bodies in this state:
    each body's bounds grown by its speculative margin (response/rows.py), for scenes that draw
    what the engine tests."""
    margin, lo, hi = np.empty(world.n), np.empty((world.n, 2)), np.empty((world.n, 2))
    velocities = np.ascontiguousarray(velocities, np.float64)
    bodies = Bodies(world.shapes, np.ascontiguousarray(positions, np.float64), velocities, world.angles,
                    world.angular_velocities, world.accelerations, world.radii, world.masses, world.inertias,
                    world.vertex_start, world.body_vertices)
    _margins_and_bounds(bodies, 1.0 / fps / substeps, margin, lo, hi)
    return lo, hi


@compiled
def _contact_phases(bodies, statics, broad, sleep, dt, margin, lo, hi, vertices, held, found, rows, prior, fast,
                    phase_cycles, t):
    """broad and narrow: the step's contact rows, from the state at its start. vertices (V, 2)
    receives the polygons' world vertices; held: statics_paths.statics_scratch's (which circles
    touch a segment); found and rows (response/rows.py) are kept from step
    to step, grown when a step needs more. Sleepers a body comes near are woken first, and then
    have their margins and pairs found again (engine/islands.py); prior: the (pairs, touching)
    of the contact phase before, which pairs of sleepers keep (all of them when every body slept
    already then: as in Box2D, a world asleep costs nothing); fast: the fast polygons
    (fast_polygons.py), whose swept ones have no wall rows. Returns (found, rows, count,
    candidate pairs, which of them touch, t)."""
    b = bodies
    n = b.positions.shape[0]
    # (the sleeping calls that count references are guarded here: a call hands numba every array
    # of the tuples it takes)
    if still(sleep, n) and prior[1].shape[0] == prior[0].shape[0]:
        fast.count[0] = 0
        return found, rows, 0, prior[0], prior[1], t   # nothing moved since the phase before
    place_any_polygons(statics.volumes, b.body_vertices, b.vertex_start, b.positions, b.angles, vertices)
    pairs = np.empty((0, 2), np.int64)
    if n >= 2:   # a lone body runs no pair phase
        _margins_and_bounds(b, dt, margin, lo, hi)
        pairs = sort_pairs(candidate_pairs(broad, lo, hi), n)
        if sleep.sleeping[0] > 0 and wake(sleep, b, vertices, margin, pairs, statics.volumes):
            _margins_and_bounds(b, dt, margin, lo, hi)
            pairs = sort_pairs(candidate_pairs(broad, lo, hi), n)
        t = _lap(phase_cycles, BROAD, t)
    else:
        margins(b.velocities, b.angular_velocities, b.accelerations, b.radii, dt, margin)
    segment_margin = segment_reach(statics.volumes, b, dt, margin, statics.segments, fast.reach)
    most = pairs.shape[0] + 4 * n   # a manifold a pair, a body and wall (the statics' grow found themselves)
    if found.shape[0] < most:
        found = new_found(most + most // 2)
    in_pair, touching = np.zeros(n, np.bool_), np.empty(pairs.shape[0], np.bool_)
    turns = may_turn(b, statics, dt, np.empty(n, np.bool_))
    k = pair_manifolds(b, vertices, margin, dt, pairs, found, 0, in_pair, touching, statics.volumes,
                       sleep.asleep, turns)
    if sleep.sleeping[0] > 0:
        keep_touching(sleep, b, vertices, pairs, touching, prior[0], prior[1], statics.volumes)
    no_wall_rows = mark_swept(statics.volumes, b, dt, in_pair, statics.restitution, statics.segments, sleep.asleep,
                              fast)
    k = wall_manifolds(b, vertices, margin, dt, statics.box, statics.rest_speed, in_pair, found, k,
                       statics.volumes, no_wall_rows)
    found, k = polygon_segment_rows(b, statics, vertices, segment_margin, found, k, sleep.asleep)
    found, k = circle_segment_rows(b, statics, margin, in_pair, held, found, k, sleep.asleep)
    found, k = circle_map_rows(b, statics, margin, in_pair, found, k, sleep.asleep)
    if rows.i.shape[0] < 2 * k:   # up to two points a manifold
        rows = new_rows(3 * k)
    count = rows_from(found, k, b, rows)
    t = _lap(phase_cycles, NARROW, t)
    return found, rows, count, pairs, touching, t


@compiled
def _log_contacts(rows, count, log, now, frame_collisions, the_map):
    """Impacts into the log, counted: between bodies (PAIR), of a body on a wall (WALL, j its
    side), a segment (SEGMENT, j the segment) or the map (MAP, j -1: the static numbered
    the_map, counted with the segments as the map's bounces are); and, not counted, the support
    of a static holding a body without an impact (SUPPORT, j the wall's side, N_WALLS + the
    segment, or the_map), so a wall's pressure includes the weight it holds."""
    log = with_room(log, count)
    for r in range(count):
        impulse = rows.hit[r] + rows.impulse[r]
        impact = was_impact(rows, r)   # (an arrival's impulse is the solve's)
        if rows.j[r] >= 0:
            if impact:
                append(log, now, PAIR, rows.i[r], rows.j[r], impulse, rows.point[r, 0], rows.point[r, 1])
                frame_collisions[PAIR] += 1
        elif impact:
            wall, kind = rows.wall[r], static_kind(rows.wall[r], the_map)
            other = wall if kind == WALL else -1 if kind == MAP else wall - N_WALLS
            append(log, now, kind, rows.i[r], other, impulse, rows.point[r, 0], rows.point[r, 1])
            frame_collisions[SEGMENT if kind == MAP else kind] += 1
        elif impulse > 0.0:
            append(log, now, SUPPORT, rows.i[r], rows.wall[r], impulse, rows.point[r, 0], rows.point[r, 1])
    return log


@compiled(nogil=True)   # engine/ahead.py runs blocks on a thread of their own
def run_frames(bodies, statics, broad, sleep, dt, substeps, step_count, out, log, memory, contacts, work, order,
               phase_cycles):
    """Advance bodies in place by out's frame count, each frame `substeps` steps of dt, filling
    out (Frames, frames.py) and appending every collision to log. memory: the contacts' impulses of the
    step before (response/warmstart.py); contacts: those the next step starts from (Contacts);
    sleep: which bodies sleep (engine/islands.py), in place (a world that never sleeps compiles
    none of it: sleep_paths.py);
    work: the step's per-body arrays (Work); order: None, or the world's number of each body where
    they are kept in cell order (cell_order.py: the frames are recorded in the world's order).
    phase_cycles (len(PHASES) + 1,) int64 receives the cycles per phase (engine/profile.py) and
    their total. Returns (log, memory, contacts, whether the log is in canonical order, the
    frame from which every body slept and none could wake, or out's frame count): every later
    frame of the block repeats that one, recorded once, and is left for the caller to fill
    (DiscreteStepper.run). The log is sorted here (eventlog.into_canonical_order) unless the
    bodies are renumbered (order): their events are sorted once, in the world's numbers
    (cell_order.events_in_world_numbers)."""
    start = cycles()
    b, s = bodies, statics
    n = b.positions.shape[0]
    lo, hi, margin, push, shift, push_turn, shift_turn, vertices, inverse_masses, inverse_inertias, moved, _, levels, \
        recorded = work
    scratch = statics_scratch(n, s.segments.shape[0])
    the_map = map_number(s.segments)   # the statics a row names: walls, segments, then the map
    statics_count = the_map + 1        # (the contacts' memory numbers them all)
    # each step's contacts are found from the state that ends the step before (so a frame's
    # candidates are those of the state it records); the first block's, from the state given
    found, rows, count, pairs, touching = contacts
    t = cycles()
    if count < 0:
        found, rows, count, pairs, touching, t = _contact_phases(b, s, broad, sleep, dt, margin, lo, hi, vertices,
                                                                 scratch[3], found, rows, (pairs, touching),
                                                                 work.fast, phase_cycles, t)
    still_since_record = recorded[4] == 1   # every body asleep at the last frame recorded, none since
    idle = False   # every body asleep since the contacts were found, to the end of the block
    idle_from = out.positions.shape[0]   # the frame the later ones repeat
    for frame in range(out.positions.shape[0]):
        frame_collisions = out.collisions[frame]
        for substep in range(substeps):
            if idle:
                break
            step_count += 1
            now = step_count * dt
            if still(sleep, n) and touching.shape[0] == pairs.shape[0]:
                # nothing moves, nothing is found or solved, and nothing can wake (no body is awake)
                # until the block ends: as in Box2D, a world asleep costs nothing. Its steps are the
                # sleepers' support alone, logged here for all of them as the full step logs it
                idle = True
                steps = (out.positions.shape[0] - frame) * substeps - substep
                if sleep.carried_count[0] > 0:
                    log = carry(sleep, log, step_count, steps, dt)
                step_count += steps - 1
                t = _lap(phase_cycles, SLEEP, t)
                break
            keep_start(s.map, scratch[2], b.positions)
            if outpaced(s.volumes, b, margin, dt, sleep.asleep):   # a pair faster than its rows can hold
                out.approximate[frame] = True
                note_outpaced(work.fast.outpaced, frame)
            v, w, m, inertia = b.velocities, b.angular_velocities, inverse_masses, inverse_inertias   # 1/m, 1/I
            if count > 0:
                collide(rows, count, v, w, b.accelerations, m, inertia, s.restitution, s.friction, s.rest_speed, dt,
                        s.iterations)
                recall(rows, count, memory, n, statics_count)
                propped = hold_contacts(s.soft, s.rigid, rows, count, b.radii, v, w, b.accelerations, m, inertia,
                                        s.friction, dt, s.iterations, s.keep, s.pulled, push, push_turn, shift,
                                        shift_turn, moved)
                out.approximate[frame] = out.approximate[frame] or propped > 0   # held: momentum is not exact
            t = _lap(phase_cycles, RESPONSE, t)
            keep_starts(s.volumes, b, work.fast)
            integrate(b.positions, b.velocities, b.accelerations, b.angles, b.angular_velocities, dt, s.keep)
            if count > 0:
                add_contact_motion(b, rows, count, push, push_turn, shift, shift_turn, dt, moved)
            t = _lap(phase_cycles, INTEGRATE, t)
            if count > 0:
                rest_contacts(s.rigid, rows, count, v, w, m, inertia, s.friction)
                log = _log_contacts(rows, count, log, now, frame_collisions, the_map)
            if sleep.carried_count[0] > 0:
                log = carry(sleep, log, step_count, 1, dt)
            remembered = remember(rows, count, n, statics_count)
            memory = (remember_sleepers(sleep, remembered, memory, n, statics_count)
                      if sleep.sleeping[0] > 0 else remembered)
            mark_held(rows, count, scratch[3], the_map)
            t = _lap(phase_cycles, RESPONSE, t)
            log = fly_swept(s.volumes, b, s, dt, work.fast, log, now, frame_collisions)   # walls met in flight
            log = statics_phase(b, s, scratch, dt, log, now, frame_collisions)
            t = _lap(phase_cycles, STATICS, t)
            if count > 0 and settle_in_map(s.map, b.positions, b.radii):
                t = _lap(phase_cycles, SETTLE, t)
            doze(sleep, b, rows, count, dt)
            t = _lap(phase_cycles, SLEEP, t)
            found, rows, count, pairs, touching, t = _contact_phases(b, s, broad, sleep, dt, margin, lo, hi,
                                                                     vertices, scratch[3], found, rows,
                                                                     (pairs, touching), work.fast, phase_cycles, t)
        out.candidates[frame] = pairs.shape[0]
        still_now = idle or still(sleep, n)
        if still_since_record and still_now:   # the same state as the frame recorded before
            copy_rows(recorded, out.hierarchy[frame], 4)
        else:
            record_levels(levels, b, pairs, vertices, touching, out.hierarchy[frame])
            copy_rows(out.hierarchy[frame], recorded, 4)
        still_since_record = still_now
        recorded[4] = still_now
        if frame <= idle_from:
            record_state(b, out, frame, n, order)
            if idle:
                idle_from = frame
        t = _lap(phase_cycles, RECORD, t)
    phase_cycles[TOTAL] += cycles() - start
    ordered = into_canonical_order(log) if order is None else False
    return log, memory, Contacts(found, rows, count, pairs, touching), ordered, idle_from


class DiscreteStepper:
    """Advances a copy of a world, a block of frames at a time."""

    def __init__(self, world, fps: float, substeps: int = 1, broadphase: str = "auto",
                 profile: Profile | None = None, rest_speed: float | None = None):
        w = world
        # accelerations copied: a sleeping body's is 0 (engine/islands.py)
        self.bodies = Bodies(w.shapes, w.positions.copy(), w.velocities.copy(), w.angles.copy(),
                             w.angular_velocities.copy(), w.accelerations.copy(), w.radii, w.masses, w.inertias,
                             w.vertex_start, w.body_vertices)
        self.sleep = new_sleep(w, rest_speed)
        # None for what the world lacks: the step then compiles no path for it (statics_paths.py)
        index = build_segment_index(w.segments, w.box) if len(w.segments) else None
        field = None if w.map is None else w.map.field
        self.dt = 1.0 / fps / substeps
        # below this approach speed a contact rests instead of bouncing: twice what the
        # acceleration adds in a step (0 without one, so a gas bounces at every speed)
        pull = float(np.max(np.hypot(w.accelerations[:, 0], w.accelerations[:, 1]))) if w.n else 0.0
        volumes = shapes_flag(w.shapes)
        self.statics = Statics(w.box, w.segments, index, field, float(w.restitution), 2.0 * pull * self.dt,
                               ITERATIONS, float(w.friction), volumes, True if pull > 0.0 else None,
                               float(w.damping) ** self.dt, *flags_of(solver_of(w)))
        self.memory = no_memory()
        # room for contacts grows with what a step finds (rows are zeroed, so room held for 8
        # contacts a body cost 0.8 GB at a million bodies)
        self.contacts = Contacts(new_found(64), new_rows(64), -1, np.empty((0, 2), np.int64), np.empty(0, np.bool_))
        self.log = new_log(64)   # emptied and reused by every block: its room, grown once, stays
        self.work = new_work(self.bodies)
        self.broad = step_state(broadphase, world)
        chosen = f"{choose(world)} (auto)" if broadphase == AUTO else broadphase
        self.broadphase = chosen if w.n >= 2 else ""
        self.substeps = int(substeps)
        self.profile = profile or Profile()
        self.step_count = 0
        self.warnings = []
        self.asleep = None   # once every body sleeps and none can wake, the state it keeps (run: idle.py)
        self.order = None   # the world's number of each of the step's bodies, kept in cell order (cell_order.py)
        if keeps_cell_order(w, self.sleep):
            b = self.bodies   # (the stepper's own copies of what it renumbers)
            self.bodies = b._replace(radii=b.radii.copy(), masses=b.masses.copy(), inertias=b.inertias.copy())
            self.order, self.cell_width = np.arange(w.n), 2.0 * float(np.max(w.radii))

    def run(self, count: int, into=None):
        """Advance `count` frames: (Frames, Events). into: where to write the frames' positions
        and velocities (new_frames), or None for new arrays."""
        if self.asleep is not None:   # every body asleep since the block before, none able to wake
            return timed_idle(self.profile, lambda: self._idle(count, into))
        b = self.bodies
        # contacts turn polygons, and circles with friction; otherwise ω stays as given
        turning = bool(np.any(b.angular_velocities != 0.0) or np.any(b.shapes != CIRCLE) or self.statics.friction > 0)
        out = new_frames(count, len(b.positions), turning, into)
        self.work.fast.outpaced[:] = 0
        parts, done, idle_from = [], 0, count
        while done < count:   # in parts that end where the bodies are renumbered
            frame = self.step_count // self.substeps
            if self.order is not None and frame % ORDER_FRAMES == 0:   # (the contacts are found again)
                self.order, self.memory = renumber(self.bodies, self.work, self.memory, self.broad, self.order,
                                                   self.statics.box, self.cell_width)
                self.contacts = self.contacts._replace(count=-1)
            part = count - done if self.order is None else min(count - done, ORDER_FRAMES - frame % ORDER_FRAMES)
            events, idle_from = self._run_part(Frames(*(a[done:done + part] for a in out)))
            parts.append(events)
            idle_from += done
            done += part
        if not turning:
            out = constant_angles(out, in_world_numbers(b.angles, self.order), in_world_numbers(b.angular_velocities,
                                                                                                self.order))
        if idle_from < count:   # (the state the later blocks repeat, kept once)
            self.asleep = tuple(a.copy() for a in (b.positions, b.velocities, b.angles, b.angular_velocities))
        out = repeat_idle(out, idle_from + 1, into is None)
        return out, parts[0] if len(parts) == 1 else Events.concatenate(parts)

    def _idle(self, count: int, into) -> tuple:
        """run(count, into) of a world asleep (idle.py)."""
        sleep, first = self.sleep, self.step_count + 1
        self.step_count += count * self.substeps
        return idle_block(count, first, count * self.substeps, self.dt, sleep.carried[:sleep.carried_count[0]],
                          self.asleep, self.contacts.pairs.shape[0], self.work.recorded[:4], into)

    def _run_part(self, out: Frames) -> tuple:
        """run_frames on out (frames of the block): their events, and the frame from which the
        later ones repeat it (out's frame count if none)."""
        self.log.size[0] = 0
        self.log, self.memory, self.contacts, ordered, idle_from = self.profile.timed(
            lambda phase_cycles: run_frames(self.bodies, self.statics, self.broad, self.sleep, self.dt, self.substeps,
                                            self.step_count, out, self.log, self.memory, self.contacts, self.work,
                                            self.order, phase_cycles))
        if out.approximate.any() and not self.warnings:
            frame = int(np.argmax(out.approximate))
            fast = self.work.fast.outpaced[0] > 0 and self.work.fast.outpaced[1] == frame
            self.warnings.append((fast_note if fast else held_note)(self.step_count // self.substeps + 1 + frame))
        self.step_count += len(out.positions) * self.substeps
        # renumbered bodies' events are sorted once, in the world's numbers (events_in_world_numbers)
        events = log_events(self.log, ordered=ordered or self.order is not None)
        return events_in_world_numbers(events, self.order), idle_from
