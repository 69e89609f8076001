"""Slow motion and freeze frames: how a panel's video time maps onto its simulation time.

A teaching scene slows down around the moment that matters and holds a frame while the
explanation appears. The simulation is untouched (it is sampled at its own fps as always);
only the player's clock changes: `Slow(start, end, factor)` plays the simulated interval
[start, end] at `factor` of real time, and `Freeze(at, seconds)` holds the sample at `at` for
`seconds` of video. The video grows by what they add (`Pace.extra`).

    RenderSettings(pace=Pace(Slow(1.2, 1.6, 0.1), Freeze(1.4, 3.0)))

`Steps(start, count, seconds, hold)` times a build shown one step at a time over a frozen frame
(on the video's clock): `Pace(Freeze(at, steps.freeze_end - at))` holds the frame for it, and
the items drawing the build ask `steps.at(state)` which step shows.
"""
from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Slow:
    start: float
    end: float
    factor: float   # 0.1 plays ten times slower

    def __post_init__(self):
        if not (0 < self.factor <= 1) or not self.end > self.start or not math.isfinite(self.end - self.start):
            raise ValueError(f"Slow needs finite times, end > start and a factor in (0, 1], got {self}")


@dataclass(frozen=True)
class Freeze:
    at: float
    seconds: float

    def __post_init__(self):
        if not self.seconds > 0 or not math.isfinite(self.at) or not math.isfinite(self.seconds):
            raise ValueError(f"Freeze needs a finite time and finite seconds > 0, got {self}")


class Pace:
    """The piecewise-linear map from video seconds to simulation seconds."""

    def __init__(self, *parts):
        self.parts = tuple(sorted(parts, key=lambda p: p.start if isinstance(p, Slow) else p.at))
        self._knots = self._build()

    def _build(self) -> list:
        """(video time, simulation time, rate) at each change of pace, from (0, 0, 1)."""
        knots, video, sim = [], 0.0, 0.0
        for part in self.parts:
            start = part.start if isinstance(part, Slow) else part.at
            if start < sim:
                raise ValueError(f"{part} overlaps the part of the pace before it")
            video += start - sim
            sim = start
            if isinstance(part, Slow):
                knots.append((video, sim, part.factor))
                video += (part.end - part.start) / part.factor
                sim = part.end
            else:
                knots.append((video, sim, 0.0))
                video += part.seconds
            knots.append((video, sim, 1.0))
        return [(0.0, 0.0, 1.0)] + knots

    @property
    def extra(self) -> float:
        """Video seconds the pace adds to the simulation's own length."""
        video, sim, _ = self._knots[-1]
        return video - sim

    def video_time(self, simulation_time: float) -> float:
        """The first video time at which `simulation_time` is shown (a freeze starts there)."""
        for (video, sim, rate), (_, next_sim, _) in zip(self._knots, self._knots[1:] + [(0, float("inf"), 0)]):
            if sim <= simulation_time <= next_sim:
                return video + (simulation_time - sim) / rate if rate > 0 else video
        return simulation_time

    def simulation_time(self, video_time: float) -> float:
        """The simulation time shown at `video_time` seconds into the panel."""
        for video, sim, rate in reversed(self._knots):
            if video_time >= video:
                return sim + rate * (video_time - video)
        return video_time


class Steps:
    """A build shown on a frozen frame: `count` steps of `seconds` each from video second
    `start`, then held `hold` seconds. `at(state)` is the step showing (-1 before the first, the
    last one after), `built(state)` whether every step has shown, `live(state)` whether the
    hold is over (the simulation plays on). `state.clock` is the panel's video clock."""

    def __init__(self, start: float, count: int, seconds: float, hold: float = 1.5):
        if count < 1 or not seconds > 0 or not hold >= 0 or not all(map(math.isfinite, (start, seconds, hold))):
            raise ValueError(f"Steps needs count >= 1, finite times, seconds > 0 and hold >= 0, got {count}, "
                             f"{seconds}, {hold}")
        self.start, self.count, self.seconds = start, count, seconds
        self.end = start + count * seconds
        self.freeze_end = self.end + hold

    def at(self, state) -> int:
        if state.clock < self.start:
            return -1
        return min(int(math.floor((state.clock - self.start) / self.seconds)), self.count - 1)

    def built(self, state) -> bool:
        return state.clock >= self.end

    def live(self, state) -> bool:
        return state.clock >= self.freeze_end
