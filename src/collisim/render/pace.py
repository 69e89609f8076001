"""Slow motion and freeze frames: how a panel's video time maps onto its simulation time.

A teaching scene slows down around the moment that matters and holds a frame while the
explanation appears. The simulation is untouched (it is sampled at its own fps as always);
only the player's clock changes: `Slow(start, end, factor)` plays the simulated interval
[start, end] at `factor` of real time, and `Freeze(at, seconds)` holds the sample at `at` for
`seconds` of video. The video grows by what they add (`Pace.extra`).

    RenderSettings(pace=Pace(Slow(1.2, 1.6, 0.1), Freeze(1.4, 3.0)))
"""
from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Slow:
    start: float
    end: float
    factor: float   # 0.1 plays ten times slower

    def __post_init__(self):
        if not (0 < self.factor <= 1) or not self.end > self.start:
            raise ValueError(f"Slow needs end > start and a factor in (0, 1], got {self}")


@dataclass(frozen=True)
class Freeze:
    at: float
    seconds: float

    def __post_init__(self):
        if not self.seconds > 0:
            raise ValueError(f"Freeze needs seconds > 0, got {self}")


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
