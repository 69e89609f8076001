"""Time spent per phase of the step, as a physics engine's profile records it."""
import time


class Profile:
    """Accumulates wall seconds per phase: `lap("broad")` charges the time since the last lap."""

    def __init__(self):
        self.seconds = {}
        self._last = time.perf_counter()

    def start(self) -> None:
        self._last = time.perf_counter()

    def lap(self, phase: str) -> None:
        now = time.perf_counter()
        self.seconds[phase] = self.seconds.get(phase, 0.0) + now - self._last
        self._last = now


def profile_table(seconds_per_phase: dict) -> str:
    """Seconds and share of the total per phase, one row each."""
    total = sum(seconds_per_phase.values()) or 1.0
    rows = [f"{'phase':<10} {'seconds':>9} {'share':>6}"]
    for phase, seconds in seconds_per_phase.items():
        rows.append(f"{phase:<10} {seconds:9.4f} {seconds / total:6.1%}")
    rows.append(f"{'total':<10} {sum(seconds_per_phase.values()):9.4f}")
    return "\n".join(rows)
