"""Functions compiled without numba's reference counting (compiling.uncounted) never return an
array, and the event loop's per-event functions are among them.

An uncounted function hands back whatever it returns without counting a reference: an array
returned that way would be freed by its caller while still in use. numba refuses an uncounted
function that allocates, but not one that returns an array it was handed, so this is checked
here on every compiled signature, after a ccd run that goes through gravity, resting, sleeping,
segments and the budget."""
import sys

import numpy as np
from numba.core import types
from numba.core.registry import CPUDispatcher

import collisim
from collisim.engine.ccd import events

# The functions an event runs; each must stay uncounted (the event loop's speed rests on it).
PER_EVENT = ("collect_collisions", "reschedule", "record_contacts", "apply_bookkeeping", "sample")


def uncounted_dispatchers():
    found = {}
    for name, module in list(sys.modules.items()):
        if not name.startswith("collisim."):
            continue
        for attr, value in vars(module).items():
            if isinstance(value, CPUDispatcher) and value.targetoptions.get("_nrt") is False:
                found[f"{value.py_func.__module__}.{value.py_func.__qualname__}"] = value
    return found


def holds_an_array(typ) -> bool:
    if isinstance(typ, types.Array):
        return True
    if isinstance(typ, types.BaseTuple):
        return any(holds_an_array(t) for t in typ.types)
    return False


def run_ccd_through_every_path():
    radius, width = 0.5, 6.0
    x = np.linspace(1.0, 5.0, 5)
    positions = np.column_stack([np.concatenate([x, x]), np.repeat([1.0, 3.0], 5)])
    world = collisim.World(positions, np.zeros((10, 2)), radius, box=(0, 0, width, 8.0), gravity=(0.0, -9.81),
                           restitution=0.5, segments=[(0.0, 6.0, 3.0, 5.0)])
    trajectory = collisim.simulate(collisim.Scene(world=world, seconds=1.5, fps=30, method="ccd"))
    assert trajectory.positions[-1, :, 1].max() < 3.0     # the balls fell and lie on the floor


def test_no_uncounted_function_returns_an_array():
    run_ccd_through_every_path()
    dispatchers = uncounted_dispatchers()
    compiled = {name: d for name, d in dispatchers.items() if d.overloads}
    assert len(compiled) >= 40, sorted(compiled)
    for name, dispatcher in compiled.items():
        for signature in dispatcher.signatures:
            returned = dispatcher.overloads[signature].signature.return_type
            assert not holds_an_array(returned), f"{name}{signature} returns {returned}"


def test_the_per_event_functions_are_uncounted():
    for name in PER_EVENT:
        assert getattr(events, name).targetoptions.get("_nrt") is False, name
