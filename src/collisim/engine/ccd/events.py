"""Method `ccd`: exact event-driven simulation, sampled at frame times.

Instead of stepping time in fixed increments and repairing overlaps, an
event-driven simulation jumps from one collision to the next:

1. predict, for every particle, when it will next hit a wall, a segment or
   another particle (time of impact, toi.py) and put those events in a
   priority queue ordered by time (eventqueue.py);
2. take the earliest event, bring the particles involved up to its time (they
   move in closed form, p + v t + ½ g t², bodies.py), apply the collision
   response (resolve.py);
3. predict again for those particles only — their other queued events are now
   out of date and are skipped when they come up (collision counters);
4. repeat. A frame boundary is just a time at which all particles are sampled.

Candidate pairs come from a cell grid whose cell crossings are events too
(grid.py, predict.py), so no collision is missed at any speed, and the work
per event stays constant as the number of particles grows.

Guards. Only approaching contacts are impacts, so a pair that has just
collided is never collided again at t + 0 by rounding, and overlapping pairs
that separate are left alone. Collisions at exactly the same time are solved
together (resolve.py), so the result does not depend on their order and
mirror-symmetric set-ups stay symmetric; everything else happens in the fixed
order (time, kind, i, j). Zeno behaviour (infinitely many collisions in a
finite time) is headed off where it usually starts: a particle that would
bounce less than a billionth of its radius rests on its wall or segment
(bodies.py), and contacts between particles under gravity never bounce lower
than an invisible micro-bounce (resolve.py). Anything that still needs more
than `max_events_per_frame` events in one frame sets budget_exceeded[f], and
the rest of the frame is skipped: the bodies keep their exact state at the last
event processed while the clock jumps to the frame time (fallback.py), so a run
never hangs, nothing overlaps and no energy is lost.

Compiled code. The state travels as namedtuples of arrays (Bodies, CellGrid,
EventQueue, Contacts), and numba would count references to every array of every
tuple handed to a function, twice a call, with atomic instructions: measured
with perf (2026-11), that was over half of an event's time on the dense gas. So
every function run at every event is compiled without numba's reference
counting (compiling.kernel): it may neither allocate nor return an array. Those handed the
state are inlined into the loop (compiling.inlined): a call hands numba's flattened tuples over
as some two hundred arguments, which cost about a third of an event's time.
A frame's events are processed by frame_events.py; when the log or the queue
might run out of room it stops and says so, and run grows them
(eventlog.with_room, eventqueue.reserve) and lets it go on. Every function is
compiled with error_model="numpy": a division by zero gives inf or nan, as in
NumPy, instead of raising (every such case is guarded anyway, so results are
the same).
"""
from collections import namedtuple
from typing import NamedTuple

import numpy as np

from ...broadphase.cells import assign_all, make_grid
from ...core.compiling import compiled, kernel
from ...core.geometry.box import clamp_into_box
from ...core.kinds import N_WALLS, PAIR, SEGMENT, WALL
from ..eventlog import new_log, with_room
from ..rest import default_rest_speed
from .bodies import FREE, Bodies, Environment, advance, position_at, velocity_at
from .carried import carry_sleepers
from .eventqueue import SLIDE_OFF, clear, new_queue, reserve
from .fallback import freeze_storm, skip_to_frame, thaw
from .frame_events import (INVOLVED, NEED, NEED_LOG, NEED_QUEUE, OVER_BUDGET, PROCESSED, STATE_SIZE, frame_events,
                           reschedule)
from .resolve import default_tc, new_contacts
from .sleep import doze_all
from .support import log_frame_supports, new_supports


class CCDResult(NamedTuple):
    """The sampled trajectory and the collisions of an event-driven run.

    F = n_frames + 1 samples, sample f at t = f * frame_dt (f = 0: the initial state).
    Collisions are listed by time, then (kind, i, j); the per-frame counts are those
    in the interval ending at sample f (0 at f = 0).
    """
    positions: np.ndarray        # (F, n, 2)
    velocities: np.ndarray       # (F, n, 2)
    time: np.ndarray             # (k,) float64
    kind: np.ndarray             # (k,) int8: 0 wall, 1 pair, 2 segment
    i: np.ndarray                # (k,) intp: the particle (the lower index for pairs)
    j: np.ndarray                # (k,) intp: the other particle, the wall (0 left 1 right 2 bottom 3 top) or segment
    impulse: np.ndarray          # (k,) float64: m |Δv_n| delivered to i (and to j for pairs)
    point: np.ndarray            # (k, 2) contact point
    wall_collisions: np.ndarray      # (F,) int64
    pair_collisions: np.ndarray      # (F,) int64
    segment_collisions: np.ndarray   # (F,) int64
    budget_exceeded: np.ndarray  # (F,) bool


@compiled(error_model="numpy")
def schedule_all(bodies, grid, env, queue, t, t_end, base, done):
    """Forget every prediction and predict everything afresh from time t."""
    n = bodies.radius.shape[0]
    clear(queue)
    for i in range(n):
        advance(bodies, i, t)
    assign_all(grid, bodies.pos)
    return reschedule_growing(bodies, grid, env, queue, np.arange(n), n, t, t_end, base, done)


@compiled(error_model="numpy")
def reschedule_growing(bodies, grid, env, queue, particles, count, t, t_end, base, done):
    """reschedule, growing the queue whenever it asks to; returns the queue. For the calls made
    once a frame: the event loop (run) writes this loop out, since a call that may allocate
    costs reference counting on every array it is handed."""
    n = bodies.radius.shape[0]
    step = reschedule(bodies, grid, env, queue, particles, count, t, t_end, base, done, -1)
    while step < count:
        queue = reserve(queue, n + count, bodies.counter, base)
        step = reschedule(bodies, grid, env, queue, particles, count, t, t_end, base, done, step)
    return queue


@kernel
def sample(bodies, t, positions, velocities):
    """Write every particle's state at time t into positions, velocities (n, 2)."""
    for i in range(bodies.radius.shape[0]):
        positions[i, 0], positions[i, 1] = position_at(bodies, i, t)
        velocities[i, 0], velocities[i, 1] = velocity_at(bodies, i, t)


EventLoop = namedtuple("EventLoop", ["bodies", "grid", "env", "queue", "contacts", "done", "listed", "involved",
                                     "base", "t_end", "supports", "tally", "resting"])
EventLoop.__doc__ = """Everything the event loop keeps from one block of frames to the next, so that a run
streamed in blocks of any size is the same run: bodies, grid, env; the event queue; scratch
(contacts, done, listed, involved); base (event key packing); t_end (the run's end: nothing
later is predicted); supports (what resting bodies' supports push with, support.py); tally (5,)
int64: the events processed so far by kind — contacts with walls, particles and segments (kinds.py),
cell crossings and slides off a segment's end (eventqueue.py) — for measuring events per second;
resting: True when bodies may come to rest or sleep (gravity, or a rest speed), None when they
never can (a gas): the loop then compiles none of resting's and sleeping's bookkeeping (support.py,
sleep.py, carried.py), which at run time would do nothing for it (about a fifth of a cold ccd
run's compiling)."""


def start_event_loop(positions, velocities, gravity, radii, masses, box, restitution, segments, t_end,
                     separate_large=True, rest_speed=None, tc=None) -> EventLoop:
    """A loop at t = 0 with every event up to t_end predicted (inputs checked and copied).
    separate_large=False sizes every cell by the largest body (broadphase/cells.py);
    rest_speed (None: sleep.default_rest_speed, 0: never sleep) and tc (the TC model's time,
    None: resolve.default_tc, 0: off) are the contact model's (sleep.py, resolve.py)."""
    positions, velocities, gravity, radii, masses, box, segments = _checked_inputs(
        positions, velocities, gravity, radii, masses, box, segments)
    if not 0.0 <= restitution <= 1.0:
        raise ValueError("need 0 <= restitution <= 1")
    n = len(positions)
    bodies = Bodies(positions, velocities, np.tile(gravity, (n, 1)), np.zeros(n), radii, masses,
                    np.full(n, FREE, np.int64), np.full(n, FREE, np.int64), np.zeros((n, 2)), np.zeros(n, np.int64),
                    np.zeros(n), np.zeros(n, np.bool_), np.full(n, -np.inf), np.full(n, np.inf), np.full(n, -np.inf))
    if rest_speed is None:
        rest_speed = default_rest_speed(gravity, radii, restitution)
    rest_speed = np.broadcast_to(np.asarray(rest_speed, np.float64), (n,)).copy()
    if tc is None:
        tc = default_tc(gravity, rest_speed)
    if not tc >= 0.0 or np.any(~(rest_speed >= 0.0)):
        raise ValueError(f"need rest_speed >= 0 and tc >= 0, got {rest_speed} and {tc}")
    env = Environment(box, segments, gravity, float(restitution), rest_speed, float(tc))
    grid = make_grid(box, radii, segments, separate_large, packed=bool(np.any(env.rest_speed > 0.0)))
    base = max(n, len(segments), N_WALLS) + 1
    done = np.zeros(n, np.bool_)
    resting = True if np.any(gravity != 0.0) or np.any(rest_speed > 0.0) else None
    loop = EventLoop(bodies, grid, env, new_queue(16 * (n + 1), n), new_contacts(4 * n + 16), done,
                     np.zeros(n, np.bool_), np.empty(n, np.int64), base, float(t_end), new_supports(n),
                     np.zeros(SLIDE_OFF + 1, np.int64), resting)
    # every event predicted by the loop itself, run for no frame: a call of schedule_all from
    # Python would compile it a second time, with Python's wrappers (the loop compiles it anyway)
    _, queue = _run(loop, resting, 1.0, 0, 0, 1, np.empty((0, n, 2)), np.empty((0, n, 2)), np.zeros((0, 3), np.int64),
                    np.zeros(0, np.bool_), True)
    return loop._replace(queue=queue)


def run(loop, frame_dt, first, count, budget, positions, velocities, counts, over_budget):
    """Frames first .. first + count - 1 of the run (frame f at t = f·frame_dt). Fills
    positions, velocities (count, n, 2), counts (count, 3) per kind and over_budget (count,)
    (frames whose last events were skipped, fallback.py). Returns the EventLog of their
    collisions in processing order and the (possibly larger) queue, which the caller keeps
    in the loop."""
    return _run(loop, loop.resting, frame_dt, first, count, budget, positions, velocities, counts, over_budget, False)


@compiled(nogil=True, error_model="numpy")   # engine/ahead.py: blocks on their own thread
def _run(loop, resting, frame_dt, first, count, budget, positions, velocities, counts, over_budget, predict):
    """run, with loop.resting as an argument: None prunes (before typing) every branch that
    `resting is not None` guards, so that they never compile (EventLoop). predict: first predict
    every event from t = 0 (start_event_loop)."""
    bodies, grid, env, queue, contacts = loop.bodies, loop.grid, loop.env, loop.queue, loop.contacts
    done, listed, involved, base, t_end = loop.done, loop.listed, loop.involved, loop.base, loop.t_end
    supports, tally = loop.supports, loop.tally
    n = bodies.radius.shape[0]
    if predict:
        queue = schedule_all(bodies, grid, env, queue, 0.0, t_end, base, done)
    may_sleep = False   # doze does nothing when no body may sleep (gases): no call at every event
    for body in range(env.rest_speed.shape[0]):
        may_sleep = may_sleep or env.rest_speed[body] > 0.0
    log = new_log(1024)
    state, clock = np.zeros(STATE_SIZE, np.int64), np.zeros(2)
    storm_bodies, rest_speeds = np.empty(n, np.int64), np.empty(n)   # fallback.freeze_storm's
    for row in range(count):
        t_frame = (first + row) * frame_dt
        state[:] = 0
        clock[:] = 0.0
        frozen = 0
        while True:   # frame_events stops to let the log or the queue grow (it cannot allocate)
            status = frame_events(bodies, grid, env, queue, contacts, log, done, listed, involved, base, t_end,
                                  supports, tally, resting, may_sleep, t_frame, budget, counts[row], state, clock)
            if status == NEED_LOG:
                log = with_room(log, state[NEED])
            elif status == NEED_QUEUE:
                queue = reserve(queue, n + state[INVOLVED], bodies.counter, base)
            else:
                if resting is not None:
                    if status == OVER_BUDGET and frozen == 0 and may_sleep:
                        # once a frame: freeze the storm, and let the rest of the frame go on without it
                        frozen = freeze_storm(bodies, grid, env, clock[1], storm_bodies, rest_speeds)
                        if frozen > 0:
                            queue = reschedule_growing(bodies, grid, env, queue, storm_bodies, frozen, clock[1], t_end,
                                                       base, done)
                            state[PROCESSED] = 0
                            continue
                break
        over_budget[row] = status == OVER_BUDGET or frozen > 0
        t_last = clock[1]
        if resting is not None:
            thaw(env, storm_bodies, frozen, rest_speeds)
            log = log_frame_supports(log, bodies, env, supports, t_frame)
        if over_budget[row]:
            skip_to_frame(bodies, env, t_last, t_frame)
            queue = schedule_all(bodies, grid, env, queue, t_frame, t_end, base, done)
        if resting is not None:
            fell = doze_all(bodies, grid, env, t_frame, involved)
            if may_sleep:
                log, fell = carry_sleepers(log, bodies, grid, env, supports, t_frame, involved, fell)
            if fell:
                queue = reschedule_growing(bodies, grid, env, queue, involved, fell, t_frame, t_end, base, done)
        sample(bodies, t_frame, positions[row], velocities[row])
    return log, queue


def _checked_inputs(positions, velocities, gravity, radii, masses, box, segments):
    """float64 copies of the inputs, after checking shapes and that the particles fit
    inside the box; centres within 1e-9 of the box size outside are moved in."""
    positions = np.array(positions, dtype=np.float64).reshape(-1, 2)
    n = len(positions)
    velocities = np.array(velocities, dtype=np.float64).reshape(n, 2)
    radii = np.broadcast_to(np.asarray(radii, dtype=np.float64), (n,)).copy()
    masses = np.broadcast_to(np.asarray(masses, dtype=np.float64), (n,)).copy()
    gravity = np.array(gravity, dtype=np.float64).reshape(2)
    box = np.array(box, dtype=np.float64).reshape(4)
    segments = np.zeros((0, 4)) if segments is None else np.array(segments, dtype=np.float64).reshape(-1, 4)
    if np.any(radii <= 0) or np.any(masses <= 0):
        raise ValueError("radii and masses must be > 0")
    lower, upper = box[:2] + radii[:, None], box[2:] - radii[:, None]
    tolerance = 1e-9 * max(box[2] - box[0], box[3] - box[1])
    if np.any(lower > upper) or np.any(positions < lower - tolerance) or np.any(positions > upper + tolerance):
        raise ValueError("every particle must lie inside the box")
    clamp_into_box(positions, radii, box)
    return positions, velocities, gravity, radii, masses, box, segments


def simulate_events(positions, velocities, gravity, radii, masses, box, restitution, segments, frame_dt, n_frames,
                    max_events_per_frame=100_000, separate_large=True, rest_speed=None, tc=None) -> CCDResult:
    """Exact event-driven simulation of n circles, sampled every frame_dt for n_frames.

    positions, velocities (n, 2); gravity (2,) the same for every particle; radii,
    masses (n,) > 0; box (xmin, ymin, xmax, ymax); restitution e in [0, 1]; segments
    (m, 4) rows (x0, y0, x1, y1) or None. Inputs are copied, never modified.
    Returns a CCDResult; F = n_frames + 1 samples, the first one the initial state.
    """
    if max_events_per_frame < 1 or n_frames < 0 or not frame_dt > 0:
        raise ValueError("need max_events_per_frame >= 1, n_frames >= 0 and frame_dt > 0")
    loop = start_event_loop(positions, velocities, gravity, radii, masses, box, restitution, segments,
                            n_frames * frame_dt, separate_large, rest_speed, tc)
    n, samples = len(loop.bodies.pos), n_frames + 1
    out_positions, out_velocities = np.empty((samples, n, 2)), np.empty((samples, n, 2))
    counts, over_budget = np.zeros((samples, 3), np.int64), np.zeros(samples, np.bool_)
    sample(loop.bodies, 0.0, out_positions[0], out_velocities[0])
    log, _ = run(loop, float(frame_dt), 1, int(n_frames), int(max_events_per_frame), out_positions[1:],
                 out_velocities[1:], counts[1:], over_budget[1:])
    time, kind, i, j, impulse, point = sorted_log(log)
    return CCDResult(out_positions, out_velocities, time, kind, i, j, impulse, point, counts[:, WALL].copy(),
                     counts[:, PAIR].copy(), counts[:, SEGMENT].copy(), over_budget)


def sorted_log(log) -> tuple:
    """The log's collisions (time, kind, i, j, impulse, point) in (time, kind, i, j) order."""
    k = log.size[0]
    time, kind, i, j = log.time[:k], log.kind[:k], log.i[:k], log.j[:k]
    order = np.arange(k)
    if k > 1 and not np.all(time[1:] > time[:-1]):  # simultaneous collisions: put them in (kind, i, j) order
        order = np.lexsort((j, i, kind, time))
    return time[order], kind[order], i[order], j[order], log.impulse[:k][order], log.point[:k][order]
