"""Time per phase of the step, counted inside the compiled loop.

A physics engine's profile (Box2D's b2Profile) times each phase of every step. Python's clock
cannot be read from compiled code, so the loop reads the processor's cycle counter (LLVM's
readcyclecounter: a few nanoseconds, cheap enough to read at every phase of every step) and
adds each phase's cycles into a small array. Around the compiled call the counter is read
together with Python's clock, which gives the counter's rate (it ticks at a constant rate on
current processors), so each phase is reported in seconds. What the call spent outside every
phase — calling, compiling on a first run — is reported as "other". On a processor without a
cycle counter every count is 0 and the whole call is reported as "step".
"""
import time

import numpy as np
from llvmlite import ir
from numba.core import cgutils, types

from ..core.compiling import kernel
from numba.extending import intrinsic

# The discrete step's phases, in the order they run.
PHASES = ("integrate", "broad", "narrow", "response", "statics", "settle", "sleep", "record")


@intrinsic
def cycles(typingctx):
    """The processor's cycle counter (int64), for timing phases inside compiled code."""
    def codegen(context, builder, signature, args):
        counter = cgutils.get_or_insert_function(builder.module, ir.FunctionType(ir.IntType(64), []),
                                                 "llvm.readcyclecounter")
        return builder.call(counter, [])
    return types.int64(), codegen


@kernel
def read_cycles():
    """The cycle counter, read from Python."""
    return cycles()


class Profile:
    """Accumulates wall seconds per phase over the compiled calls of a run."""

    def __init__(self):
        self.seconds = {}

    def add(self, phase: str, seconds: float) -> None:
        self.seconds[phase] = self.seconds.get(phase, 0.0) + seconds

    def timed(self, call, phases=PHASES):
        """Run call(phase_cycles) — a compiled call that adds cycles per phase into
        phase_cycles (len(phases) + 1,), the last entry being its own total — and add the
        phases' seconds to the profile. Returns call's result."""
        phase_cycles = np.zeros(len(phases) + 1, np.int64)
        start_cycles, start = read_cycles(), time.perf_counter()
        result = call(phase_cycles)
        wall, elapsed_cycles = time.perf_counter() - start, read_cycles() - start_cycles
        if elapsed_cycles <= 0 or phase_cycles[-1] <= 0:
            self.add("step", wall)
            return result
        seconds_per_cycle = wall / elapsed_cycles
        for phase, count in zip(phases, phase_cycles[:-1]):
            self.add(phase, float(count * seconds_per_cycle))
        self.add("other", float((elapsed_cycles - phase_cycles[:-1].sum()) * seconds_per_cycle))
        return result


def profile_table(seconds_per_phase: dict) -> str:
    """Seconds and share of the total per phase, one row each."""
    total = sum(seconds_per_phase.values()) or 1.0
    rows = [f"{'phase':<10} {'seconds':>9} {'share':>6}"]
    for phase, seconds in seconds_per_phase.items():
        rows.append(f"{phase:<10} {seconds:9.4f} {seconds / total:6.1%}")
    rows.append(f"{'total':<10} {sum(seconds_per_phase.values()):9.4f}")
    return "\n".join(rows)
