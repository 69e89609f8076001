"""The events of one frame, in the order they happen: each taken from the queue, resolved, and
its particles predicted again (events.py says how the whole method works).

Everything here runs at every event, so it allocates nothing. When the event log or the queue might run out of
room, frame_events stops where it is, says what it needs (NEED_LOG, NEED_QUEUE), and the caller
(events.run) grows it and calls again: the event goes on from that point, so a frame is the
same whatever the log's and the queue's sizes were.
"""
from ...core.compiling import inlined, kernel
from ...core.geometry.circle import line_of_centres
from ...core.kinds import PAIR, SEGMENT, WALL
from ...broadphase.cells import move
from ..eventlog import append, has_room as log_has_room
from .bodies import advance, release
from .carried import note_sleepers, take_hits
from .eventqueue import CELL, event_key, has_room, is_current, key_parts, pop, push_one_body
from .predict import predict_pairs, predict_solo
from .resolve import add_pair_contact, add_segment_contact, add_wall_contact, mark_hits, settle_resting, solve_contacts
from .sleep import doze, wake_up
from .support import note_supports

# What frame_events returns: the frame is done, or stopped at its budget with events left, or it
# needs the caller to give the log room for state[NEED] more rows, or the queue room for
# n + state[INVOLVED] events.
DONE, OVER_BUDGET, NEED_LOG, NEED_QUEUE = 0, 1, 2, 3
# Where an event stands (state[STAGE]): between events, resolved and to be logged, being predicted.
BETWEEN, LOGGING, PREDICTING = 0, 1, 2
# The fields of the state (int64) an interrupted frame goes on from; clock (2,) float64 holds the
# event's time and the time of the last event processed.
STAGE, INVOLVED, STEP, PROCESSED, COLLISION, NEED = range(6)
STATE_SIZE = 6


@kernel
def frame_events(bodies, grid, env, queue, contacts, log, done, listed, involved, base, t_end, supports, tally,
                 resting, may_sleep, t_frame, budget, frame_counts, state, clock):
    """Process the events up to t_frame (events.run's loop), going on from `state` and `clock`
    (all zero at the frame's start). Returns DONE, OVER_BUDGET (budget events were processed and
    more are due before t_frame), or NEED_LOG / NEED_QUEUE with the state to go on from.
    clock[1]: the time of the last event processed. resting: None when no body can ever rest or
    sleep (EventLoop.resting), which prunes the supports' and sleepers' bookkeeping."""
    stage, n_involved, step = state[STAGE], state[INVOLVED], state[STEP]
    processed, collision, t = state[PROCESSED], state[COLLISION], clock[0]
    status = DONE
    while True:
        if stage == BETWEEN:
            while queue.size[0] > 0 and queue.time[0] <= t_frame and not is_current(queue, 0, bodies.counter, base):
                pop(queue)
            if queue.size[0] == 0 or queue.time[0] > t_frame:
                break
            if processed >= budget:
                status = OVER_BUDGET
                break
            t, key = pop(queue)[:2]
            clock[1] = t
            kind, i, j = key_parts(key, base)
            collision = kind <= SEGMENT
            if collision:
                n_involved = collect_collisions(bodies, grid, env, queue, contacts, t, key, base, involved, listed,
                                                resting)
                solve_contacts(bodies, contacts)
                settle_resting(bodies, env, contacts)
                if resting is not None:
                    if may_sleep:
                        doze(bodies, grid, env, contacts, involved, n_involved, t)
                        take_hits(supports, contacts)
                mark_hits(bodies, contacts, t)
                processed += contacts.count[0]
            else:
                apply_bookkeeping(bodies, grid, env, kind, i, j, t)
                tally[kind] += 1
                involved[0], n_involved = i, 1
                processed += 1
            stage = LOGGING
        if stage == LOGGING:
            need = (contacts.count[0] if collision else 0) + 4 * n_involved
            if not log_has_room(log, need):
                state[NEED], status = need, NEED_LOG
                break
            if collision:
                record_contacts(log, contacts, t, frame_counts, tally)
            if resting is not None:
                if may_sleep:
                    note_sleepers(log, bodies, grid, env, supports, involved, n_involved, t)
                note_supports(log, bodies, env, supports, involved, n_involved, t)
            stage, step = PREDICTING, -1
        if stage == PREDICTING:
            step = reschedule(bodies, grid, env, queue, involved, n_involved, t, t_end, base, done, step)
            if step < n_involved:
                status = NEED_QUEUE
                break
            stage = BETWEEN
    state[STAGE], state[INVOLVED], state[STEP] = stage, n_involved, step
    state[PROCESSED], state[COLLISION], clock[0] = processed, collision, t
    return status


@inlined
def reschedule(bodies, grid, env, queue, particles, count, t, t_end, base, done, step):
    """New predictions from time t for the (current) particles particles[:count] of an event,
    from `step` on: -1 first counts a collision for each (their queued events go out of date)
    and queues each one's next one-particle event, k >= 0 queues the pairs of particles[k:].

    Returns count when done, or the step to go on from once the queue has grown: it stops
    where it might run out of room (n events a particle), since growing allocates, and a
    function that may allocate makes numba count references on every array it is handed.
    done (n,) bool is all False on entry and once done; it marks the particles whose pairs
    are predicted already, so that no pair is queued twice."""
    n = bodies.radius.shape[0]
    counter = bodies.counter
    if step < 0:
        if not has_room(queue, count):
            return step
        for k in range(count):
            counter[particles[k]] += 1
        for k in range(count):
            i = particles[k]
            t_event, kind, j = predict_solo(bodies, grid, env, i, t, t_end)
            if j >= 0:
                push_one_body(queue, t_event, event_key(kind, i, j, base), counter[i], i)
        step = 0
    for k in range(step, count):
        if not has_room(queue, n):
            return k
        predict_pairs(bodies, grid, queue, particles[k], t, done, base)
        done[particles[k]] = True
    for k in range(count):
        done[particles[k]] = False
    return count


@kernel
def _involve(bodies, i, t, involved, count, listed):
    """Add particle i to the involved particles (once), brought to time t. Returns the
    new count."""
    if listed[i]:
        return count
    listed[i] = True
    advance(bodies, i, t)
    involved[count] = i
    return count + 1


@inlined
def collect_collisions(bodies, grid, env, queue, contacts, t, key, base, involved, listed, resting):
    """Turn the collision `key` at time t (just popped) and every other current collision
    at exactly the same time into contacts, taking them off the queue. Fills involved
    with the particles concerned (and those a hard hit on a sleeper wakes: only where bodies
    may rest, `resting` not None) and returns their number."""
    contacts.count[0] = 0
    count = 0
    while True:
        kind, i, j = key_parts(key, base)
        count = _involve(bodies, i, t, involved, count, listed)
        if kind == PAIR:
            count = _involve(bodies, j, t, involved, count, listed)
            if resting is not None:
                if bodies.asleep[i] != bodies.asleep[j]:
                    count = _wake_if_hit_hard(bodies, grid, env, i, j, t, involved, count, listed)
            add_pair_contact(bodies, env, contacts, i, j)
        elif kind == WALL:
            add_wall_contact(bodies, env, contacts, i, j)
        else:
            add_segment_contact(bodies, env, contacts, i, j)
        while queue.size[0] > 0 and queue.time[0] == t and not is_current(queue, 0, bodies.counter, base):
            pop(queue)
        if (queue.size[0] == 0 or queue.time[0] != t or key_parts(queue.key[0], base)[0] > SEGMENT
                or contacts.count[0] == contacts.kind.shape[0]):
            break
        key = pop(queue)[1]
    for k in range(contacts.count[0]):
        if contacts.j[k] >= 0:  # a collision with a particle ends resting; settle_resting may restore it
            release(bodies, env, contacts.i[k])
            release(bodies, env, contacts.j[k])
    for k in range(count):   # a loop, not listed[involved[:count]]: fancy indexing may raise
        listed[involved[k]] = False
    return count


@kernel
def _wake_if_hit_hard(bodies, grid, env, i, j, t, involved, count, listed):
    """A pair (current) where one sleeps (the caller checks): a hit faster than the sleeper's rest speed
    wakes it (and what rests on it, sleep.py). Returns the new count of involved particles."""
    sleeper = i if bodies.asleep[i] else j
    nx, ny, _ = line_of_centres(bodies.pos, i, j)
    approach = (bodies.vel[i, 0] - bodies.vel[j, 0]) * nx + (bodies.vel[i, 1] - bodies.vel[j, 1]) * ny
    if approach > env.rest_speed[sleeper]:
        count = wake_up(bodies, grid, env, sleeper, t, involved, count, listed)
    return count


@kernel
def record_contacts(log, contacts, t, frame_counts, tally):
    """Log the contacts that delivered an impulse and count them by kind (a pair as i < j);
    count every contact processed in tally (EventLoop.tally). The caller makes room in the log
    (with_room): run at every event, this function allocates nothing."""
    for k in range(contacts.count[0]):
        tally[contacts.kind[k]] += 1
        if contacts.impulse[k] > 0.0:
            i, other = contacts.i[k], contacts.other[k]
            if contacts.kind[k] == PAIR and other < i:   # a contact with a sleeper is the awake one's
                i, other = other, i
            append(log, t, contacts.kind[k], i, other, contacts.impulse[k], contacts.x[k], contacts.y[k])
            frame_counts[contacts.kind[k]] += 1


@kernel
def apply_bookkeeping(bodies, grid, env, kind, i, j, t):
    """A cell crossing (move i to the next cell in direction j) or a slide off a segment's end."""
    advance(bodies, i, t)
    if kind == CELL:   # directions 0 -x, 1 +x, 2 -y, 3 +y (written out: indexing a tuple may raise)
        step = -1 if j == 0 else 1 if j == 1 else -grid.nx if j == 2 else grid.nx
        move(grid, i, grid.cell[i] + step)
    else:
        release(bodies, env, i)
