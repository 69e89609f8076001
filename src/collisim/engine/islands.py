"""Sleeping, for the discrete method: bodies at rest cost nothing until something comes near them.

Each step's contact rows join the bodies they link into *islands* (walls and segments join
nothing: they do not move). A body is *still* while it moves slower than its rest speed, its
turning moves its rim slower than that too, and neither has changed since it became still by
more than DRIFT of its rest speed. Slow is not enough: a box sliding down a slope its friction
almost holds, a ball on a gentle slope or one starting to roll down it move slower than their
rest speed for a second or more while gravity, which their contacts cannot cancel, keeps
speeding them up; asleep they would never move again. A body
its contacts hold has its weight cancelled at every step, so its velocity stays where it was to
within the solver's rounding (1e-7 of its rest speed over half a second, a box held by friction
on a 30° slope): a velocity that keeps changing is a force the contacts do not hold, and the
body's still time starts again. A body slowing to rest (a bounce dying out, a slide braking)
is held from the time it has stopped. Sleeping thus never freezes an acceleration above
DRIFT · rest speed / SLEEP_TIME (0.6 % of g for a ball of radius 0.5, as √r), which it could
not tell from the solver's rocking of a tall column. An island whose bodies have all been still for
SLEEP_TIME falls asleep as a whole — as in Box2D and Chipmunk, whose islands sleep after
half a second still (Box2D's b2_timeToSleep). The rest speed is the ccd method's
(engine/rest.py: default_rest_speed; Scene.rest_speed states it): the speed of a bounce a
thousandth of a body's radius high, and 0 (never sleep) without gravity or with e = 1, so gases
and elastic scenes run exactly as without sleeping.

A sleeping body
* has no velocity, no turning and no acceleration, so the step leaves it where it is;
* has no contact rows: the pairs of two sleepers, and a sleeper's walls and segments, are not
  looked at (the funnel of bounding volumes still counts its pairs, by the exact test alone);
* goes on pressing the walls and segments it rested on with the impulses it had there when it
  fell asleep, logged as SUPPORT at every step: a wall's pressure still includes its weight.

It wakes, with its whole island, when an awake body comes within reach: when the two have a
manifold point closer than the sum of their margins — exactly when the contact phase would give
the pair a row (response/pair_rows.py: pair_reaches). The island is then solved with the newcomer in
the same step. Falling asleep takes out at most ½·m·v_rest² + ½·I·(v_rest / r)² of kinetic
energy per body.

The state (Sleep) is per body, kept from block to block: rest speed (n,), seconds still (n,),
the velocity and turning (n, 3) vx, vy, ω the body had when it became still, asleep (n,) bool,
island (n,) (the smallest body index in the island it fell asleep with), its
acceleration while awake (n, 2), scratch for the islands, and the carried support (c, 5):
body, wall (N_WALLS + k for segment k), impulse per step, point x, y, in (body, wall) order:
the order of the events (model/trajectory.py: Events), so that the steps of a world fully
asleep log them in order and the block's events need no sorting.
"""
from collections import namedtuple

import numpy as np

from ..core.compiling import compiled, inlined, kernel
from ..core.geometry.vector import length
from ..core.kinds import CIRCLE, SUPPORT
from ..narrowphase.manifold import body_pair_touch
from ..response.pair_rows import pair_reaches
from ..response.warmstart import Memory, key_bodies
from .eventlog import append, with_room
from .rest import default_rest_speed

SLEEP_TIME = 0.5   # seconds an island must be still before it sleeps (Box2D's b2_timeToSleep)
# The change of velocity, as a fraction of the rest speed, that ends a body's still time: far
# above the solver's noise on a held body, below what gravity adds in SLEEP_TIME to a slide at
# 1 % of g or a ball on a 1° slope (tests/test_sleep_motion.py). The rocking the solver can
# leave in a tall column of tilted boxes is of the same size, and keeps such a column awake
# longer: a body the solver still moves is not frozen.
DRIFT = 0.3

Sleep = namedtuple("Sleep", ["on", "speed", "still", "since", "asleep", "fresh", "island", "pull", "parent", "least",
                             "carried", "carried_count", "sleeping"])


def new_sleep(world, rest_speed=None) -> Sleep:
    """The sleeping state of a world's n bodies at the start: all awake. rest_speed: None for the
    default (ccd's: default_rest_speed), 0 for never, or a speed; sleeping is off (`on` None, so
    that the step compiles no sleeping: sleep_paths.py; its per-body arrays empty) when every
    body's rest speed is 0."""
    n = world.n
    if rest_speed is None:
        rest_speed = default_rest_speed(world.gravity, world.radii, world.restitution) if n else np.zeros(0)
    speed = np.broadcast_to(np.asarray(rest_speed, np.float64), (n,)).copy()
    on = bool(np.any(speed > 0.0))
    m = n if on else 0
    # room for the carried support: a row a body on a wall, two for a polygon's face (and some
    # for bodies in corners); an island with more does not sleep
    room = (2 * m if np.any(world.shapes != CIRCLE) else m) + 16 if on else 0
    return Sleep(True if on else None, speed, np.zeros(m), np.zeros((m, 3)), np.zeros(n, np.bool_), np.zeros(m, np.bool_),
                 np.zeros(m, np.int64), np.array(world.accelerations[:m], np.float64), np.empty(m, np.int64),
                 np.empty(m), np.empty((room, 5)), np.zeros(1, np.int64), np.zeros(1, np.int64))


@kernel
def _root(parent, i):
    """The island of body i (union-find, with path halving)."""
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


@kernel
def _islands(parent, rows, count, n):
    """parent (n,) <- islands of the rows' pairs; each island's root is its smallest body."""
    for i in range(n):
        parent[i] = i
    for r in range(count):
        if rows.j[r] >= 0:
            a, b = _root(parent, rows.i[r]), _root(parent, rows.j[r])
            if a != b:
                parent[max(a, b)] = min(a, b)


@inlined
def _drift(sleep, bodies, i):
    """How far body i's velocity and its rim's speed have changed since it became still."""
    v, since = bodies.velocities, sleep.since
    turned = abs(bodies.angular_velocities[i] - since[i, 2]) * bodies.radii[i]
    return max(length(v[i, 0] - since[i, 0], v[i, 1] - since[i, 1]), turned)


@kernel
def _count_still(sleep, bodies, dt):
    """Add dt to the still time of each awake body slower than its rest speed (rim included)
    whose velocity has not drifted since it became still (see the module); start the still time
    again of those that drifted, at their velocity now, and reset the others'. Is any body still
    long enough to sleep?"""
    b, ready = bodies, False
    for i in range(b.positions.shape[0]):
        if sleep.asleep[i]:
            continue
        rim = abs(b.angular_velocities[i]) * b.radii[i]
        if length(b.velocities[i, 0], b.velocities[i, 1]) < sleep.speed[i] and rim < sleep.speed[i]:
            if sleep.still[i] == 0.0 or _drift(sleep, b, i) > DRIFT * sleep.speed[i]:
                sleep.still[i] = 0.0   # still from here: the velocity it must keep
                sleep.since[i, 0], sleep.since[i, 1] = b.velocities[i, 0], b.velocities[i, 1]
                sleep.since[i, 2] = b.angular_velocities[i]
            sleep.still[i] += dt
            ready = ready or sleep.still[i] >= SLEEP_TIME
        else:
            sleep.still[i] = 0.0
    return ready


@inlined
def _carried(rows, r, parent, least):
    """Is row r the support of a body on a wall or segment, in an island that falls asleep?"""
    return rows.j[r] < 0 and rows.impulse[r] > 0.0 and least[_root(parent, rows.i[r])] >= SLEEP_TIME


@kernel
def fall_asleep(sleep, bodies, rows, count, dt):
    """After a step whose contact rows (rows[:count]) were solved: count each body's still time,
    and put to sleep every island whose bodies have all been still for SLEEP_TIME, keeping its
    support on the walls and segments (see the module)."""
    if not sleep.on:
        return
    sleep.fresh[:] = False
    if not _count_still(sleep, bodies, dt):
        return
    b, parent, least = bodies, sleep.parent, sleep.least
    n = b.positions.shape[0]
    _islands(parent, rows, count, n)
    least[:] = np.inf
    for i in range(n):
        if not sleep.asleep[i]:
            root = _root(parent, i)
            least[root] = min(least[root], sleep.still[i])
    carried, k = sleep.carried, sleep.carried_count[0]
    need = 0
    for r in range(count):
        need += _carried(rows, r, parent, least)
    if k + need > carried.shape[0]:
        return   # no room for their support (see new_sleep): they stay awake
    for r in range(count):
        if _carried(rows, r, parent, least):   # put in (body, static) order (see the module), after its equals
            at = k
            while at > 0 and (carried[at - 1, 0] > rows.i[r] or
                              (carried[at - 1, 0] == rows.i[r] and carried[at - 1, 1] > rows.wall[r])):
                for column in range(5):
                    carried[at, column] = carried[at - 1, column]
                at -= 1
            carried[at, 0], carried[at, 1], carried[at, 2] = rows.i[r], rows.wall[r], rows.impulse[r]
            carried[at, 3], carried[at, 4] = rows.point[r, 0], rows.point[r, 1]
            k += 1
    sleep.carried_count[0] = k
    for i in range(n):
        if not sleep.asleep[i] and least[_root(parent, i)] >= SLEEP_TIME:
            sleep.asleep[i], sleep.fresh[i], sleep.island[i] = True, True, _root(parent, i)
            b.velocities[i, 0] = b.velocities[i, 1] = b.angular_velocities[i] = 0.0
            b.accelerations[i, 0] = b.accelerations[i, 1] = 0.0
            sleep.sleeping[0] += 1


@kernel
def all_still(sleep, n):
    """Does every one of the n bodies sleep, none of them since the last step's contacts were
    found? (Nothing has moved since: the step has nothing to find, solve or count.) Called at
    every step."""
    if n == 0 or sleep.sleeping[0] < n:
        return False
    for i in range(n):
        if sleep.fresh[i]:
            return False
    return True


@kernel
def _wake_island(sleep, bodies, island):
    """Wake every body of a sleeping island, and drop its carried support."""
    for i in range(bodies.positions.shape[0]):
        if sleep.asleep[i] and sleep.island[i] == island:
            sleep.asleep[i], sleep.still[i] = False, 0.0
            bodies.accelerations[i, 0], bodies.accelerations[i, 1] = sleep.pull[i, 0], sleep.pull[i, 1]
            sleep.sleeping[0] -= 1
    kept = 0
    for c in range(sleep.carried_count[0]):
        if sleep.asleep[int(sleep.carried[c, 0])]:
            for column in range(sleep.carried.shape[1]):   # (not a row assignment: arrays.copy_rows)
                sleep.carried[kept, column] = sleep.carried[c, column]
            kept += 1
    sleep.carried_count[0] = kept


@compiled
def wake_near(sleep, bodies, vertices, margin, pairs, polygons):
    """Before a step's contacts are found: wake the island of every sleeper that a candidate
    pair (k, 2) puts within reach of an awake body (and so on, as woken bodies reach further
    sleepers). Did any wake? vertices: the polygons' world vertices; polygons as for
    response/rows.py: pair_manifolds."""
    if sleep.sleeping[0] == 0:
        return False
    woke, again = False, True
    while again:
        again = False
        for c in range(pairs.shape[0]):
            i, j = pairs[c, 0], pairs[c, 1]
            if sleep.asleep[i] != sleep.asleep[j] and pair_reaches(bodies, vertices, margin, i, j, polygons):
                _wake_island(sleep, bodies, sleep.island[i] if sleep.asleep[i] else sleep.island[j])
                woke = again = True
    return woke


@compiled
def sleepers_touching(sleep, bodies, vertices, pairs, touching, prior_pairs, prior_touching, polygons):
    """touching (k,) <- whether the shapes of each candidate pair of two sleepers touch (pairs of
    sleepers have no manifold: response/rows.py: pair_manifolds): as the contact phase before
    found it if both slept then too (neither has moved since), else by the exact test. pairs and
    prior_pairs (p, 2) in canonical order; prior_touching (p,), or empty if unknown."""
    if sleep.sleeping[0] == 0:
        return
    b, asleep, fresh = bodies, sleep.asleep, sleep.fresh
    known = prior_touching.shape[0] == prior_pairs.shape[0]
    p = 0
    for c in range(pairs.shape[0]):
        i, j = pairs[c, 0], pairs[c, 1]
        if not (asleep[i] and asleep[j]):
            continue
        if known and not (fresh[i] or fresh[j]):
            while p < prior_pairs.shape[0] and (prior_pairs[p, 0] < i or (prior_pairs[p, 0] == i and
                                                                            prior_pairs[p, 1] < j)):
                p += 1
            if p < prior_pairs.shape[0] and prior_pairs[p, 0] == i and prior_pairs[p, 1] == j:
                touching[c] = prior_touching[p]
                continue
        touching[c] = body_pair_touch(polygons, b.shapes, b.positions, b.radii, vertices, b.vertex_start, i, j)


@kernel
def _sleeps(asleep, key, n, statics):
    """Do the bodies of warmstart.row_key's contact `key` sleep (a wall or segment always does)?
    (Handed one array, not the Sleep tuple: a call costs a reference count of every array.)"""
    i, other = key_bodies(key, n, statics)
    return asleep[i] and (other >= n or asleep[other])


@compiled
def keep_sleepers(sleep, memory, prior, n, statics):
    """The warm-start memory (response/warmstart.py) of this step's rows, with the contacts of
    sleepers kept from the memory before: a woken island starts its solve from the impulses it
    slept with. (Rows never join a sleeper, so the two sets of keys are apart.)"""
    if sleep.sleeping[0] == 0:
        return memory
    kept = 0
    for k in range(prior.keys.shape[0]):
        kept += _sleeps(sleep.asleep, prior.keys[k], n, statics)
    if kept == 0:
        return memory
    if kept == prior.keys.shape[0] and memory.keys.shape[0] == 0:
        return prior   # nothing awake in contact: the sleepers' memory as it was
    total = memory.keys.shape[0] + kept
    keys, impulses, frictions = np.empty(total, np.int64), np.empty(total), np.empty(total)
    a, k = 0, 0
    for out in range(total):   # merge the two ascending key lists
        while k < prior.keys.shape[0] and not _sleeps(sleep.asleep, prior.keys[k], n, statics):
            k += 1
        take_prior = k < prior.keys.shape[0] and (a >= memory.keys.shape[0] or prior.keys[k] < memory.keys[a])
        if take_prior:
            keys[out], impulses[out], frictions[out] = prior.keys[k], prior.impulses[k], prior.frictions[k]
            k += 1
        else:
            keys[out], impulses[out], frictions[out] = memory.keys[a], memory.impulses[a], memory.frictions[a]
            a += 1
    return Memory(keys, impulses, frictions)


@compiled
def log_carried(sleep, log, first, steps, dt):
    """The support sleepers give the walls and segments they rest on, into the log (SUPPORT), at
    each of `steps` steps of dt from step number `first` (at time first · dt): every step of a
    world fully asleep in one call."""
    count = sleep.carried_count[0]
    if count == 0:
        return log
    log = with_room(log, count * steps)
    c = sleep.carried
    for step in range(first, first + steps):
        now = step * dt
        for k in range(count):
            append(log, now, SUPPORT, int(c[k, 0]), int(c[k, 1]), c[k, 2], c[k, 3], c[k, 4])
    return log
