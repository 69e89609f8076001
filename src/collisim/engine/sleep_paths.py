"""Sleeping, compiled only for worlds whose bodies may sleep (engine/islands.py).

A world sleeps only under gravity with e < 1 (or a rest speed the scene states): a gas, an
elastic scene or a world without gravity never does. Its Sleep then has `on` None (new_sleep),
and each function below — one name whose implementation numba picks by the type of that field
when the step compiles, as statics_paths.py does for segments and maps — is a no-op: the step
of such a world never compiles the islands, the waking, the carried support nor the sleepers'
warm-start memory (twelve compiles: particles_250's cold first frame took 3 to 10 CPU seconds
less without them, alternating runs). A world that may sleep compiles its own step, cached on
its own, with `on` True.
"""
from numba.core import types
from numba.extending import overload

from .islands import all_still, fall_asleep, keep_sleepers, log_carried, sleepers_touching, wake_near


def _never(sleep_type) -> bool:
    """Whether a Sleep namedtuple type is that of a world that never sleeps (`on` None)."""
    return isinstance(sleep_type.types[sleep_type.fields.index("on")], types.NoneType)


def still(sleep, n):
    """Does every one of the n bodies sleep, none of them since the last contact phase
    (islands.all_still)? Compiled code only."""
    raise NotImplementedError("still is called from compiled code")


def wake(sleep, bodies, vertices, margin, pairs, polygons):
    """Wake the sleepers an awake body comes near (islands.wake_near); whether any woke."""
    raise NotImplementedError("wake is called from compiled code")


def keep_touching(sleep, bodies, vertices, pairs, touching, prior_pairs, prior_touching, polygons):
    """Pairs of sleepers keep the touching found before (islands.sleepers_touching)."""
    raise NotImplementedError("keep_touching is called from compiled code")


def carry(sleep, log, first, steps, dt):
    """Log the support the sleepers rest on at `steps` steps of dt from step number `first`
    (islands.log_carried); returns the log."""
    raise NotImplementedError("carry is called from compiled code")


def remember_sleepers(sleep, remembered, prior, n, statics):
    """The warm-start memory with the sleepers' kept (islands.keep_sleepers)."""
    raise NotImplementedError("remember_sleepers is called from compiled code")


def doze(sleep, bodies, rows, count, dt):
    """Islands still long enough fall asleep (islands.fall_asleep)."""
    raise NotImplementedError("doze is called from compiled code")


@overload(still)
def _still(sleep, n):
    if _never(sleep):
        return lambda sleep, n: False
    return lambda sleep, n: all_still(sleep, n)


@overload(wake)
def _wake(sleep, bodies, vertices, margin, pairs, polygons):
    if _never(sleep):
        return lambda sleep, bodies, vertices, margin, pairs, polygons: False
    return lambda sleep, bodies, vertices, margin, pairs, polygons: wake_near(sleep, bodies, vertices, margin, pairs,
                                                                              polygons)


@overload(keep_touching)
def _keep_touching(sleep, bodies, vertices, pairs, touching, prior_pairs, prior_touching, polygons):
    if _never(sleep):
        return lambda sleep, bodies, vertices, pairs, touching, prior_pairs, prior_touching, polygons: None

    def keep(sleep, bodies, vertices, pairs, touching, prior_pairs, prior_touching, polygons):
        sleepers_touching(sleep, bodies, vertices, pairs, touching, prior_pairs, prior_touching, polygons)
    return keep


@overload(carry)
def _carry(sleep, log, first, steps, dt):
    if _never(sleep):
        return lambda sleep, log, first, steps, dt: log
    return lambda sleep, log, first, steps, dt: log_carried(sleep, log, first, steps, dt)


@overload(remember_sleepers)
def _remember_sleepers(sleep, remembered, prior, n, statics):
    if _never(sleep):
        return lambda sleep, remembered, prior, n, statics: remembered
    return lambda sleep, remembered, prior, n, statics: keep_sleepers(sleep, remembered, prior, n, statics)


@overload(doze)
def _doze(sleep, bodies, rows, count, dt):
    if _never(sleep):
        return lambda sleep, bodies, rows, count, dt: None

    return lambda sleep, bodies, rows, count, dt: fall_asleep(sleep, bodies, rows, count, dt)
