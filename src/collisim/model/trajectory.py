"""What a simulation returns: the state at every frame time and its collision events; and the
trajectory file (`Trajectory.save`, `load_trajectory`), so a run can be rendered later."""
from __future__ import annotations

import json
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..core.checks import StaticMap
from ..core.files import written_whole
from .bodyshapes import polygons_of
from .world import World

FILE_FORMAT = 1  # the version of the trajectory file written by save()
# Trajectory.hierarchy's columns: the slides' bounding volumes, coarsest first (narrowphase/hierarchy.py)
LEVELS = ("bounding circle", "box", "oriented box", "shape")
NOT_COUNTED = -1   # the hierarchy of a frame nothing counted
_EVENT_FIELDS = ("time", "kind", "i", "j", "impulse", "point")
_FRAME_FIELDS = ("times", "positions", "velocities", "angles", "angular_velocities", "wall_collisions",
                 "pair_collisions", "segment_collisions", "candidates", "approximate", "hierarchy")
_WORLD_FIELDS = ("positions", "velocities", "angles", "angular_velocities", "accelerations", "gravity", "radii",
                 "masses", "colors", "box", "segments")


def canonical_order(time, kind, i, j) -> np.ndarray:
    """np.lexsort((j, i, kind, time)): the stable order of events by time, kind, i, j. A log's
    times never decrease (the steps are logged in turn), so each event's key is one integer, its
    time's rank, kind, i and j + 1 packed so that they compare as the four would, and one stable
    sort of those merges the sorted runs the log is made of instead of sorting four times
    (docs/benchmarks.md). Times out of order, or keys too large for int64, take lexsort."""
    kind, i, j = (np.asarray(a, np.int64) for a in (kind, i, j))
    plain = len(time) >= 2 and i.min() >= 0 and j.min() >= -1 and 0 <= kind.min() <= kind.max() < 8
    if not plain or np.any(time[1:] < time[:-1]):
        return np.lexsort((j, i, kind, time))
    span = max(int(i.max()), int(j.max()) + 1) + 1          # i and j + 1 lie in 0 .. span - 1
    rank = np.zeros(len(time), np.int64)
    np.cumsum(time[1:] != time[:-1], out=rank[1:])
    if (int(rank[-1]) + 1) * 8 * span * span >= 2 ** 62:
        return np.lexsort((j, i, kind, time))
    return np.argsort(((rank * 8 + kind) * span + i) * span + (j + 1), kind="stable")


@dataclass
class Events:
    """Collision events, one row each, sorted by (time, kind, i, j).

    time: (k,)      when the impact happened (the discrete method: the end of the step that found it)
    kind: (k,) int8 kinds.WALL, PAIR, SEGMENT, MAP, or SUPPORT (a resting body's support, not a collision)
    i: (k,)         the body
    j: (k,)         the other body (PAIR, i < j), the wall (WALL: kinds.WALL_SIDES), the segment, or the
                    support (SUPPORT: a wall side, kinds.N_WALLS + the segment, or kinds.N_WALLS + the
                    number of segments for the collision map)
    impulse: (k,)   magnitude of the impulse on body i along the contact normal
    point: (k, 2)   contact point
    """
    time: np.ndarray
    kind: np.ndarray
    i: np.ndarray
    j: np.ndarray
    impulse: np.ndarray
    point: np.ndarray

    @classmethod
    def empty(cls) -> "Events":
        return cls(np.zeros(0), np.zeros(0, np.int8), np.zeros(0, np.intp), np.zeros(0, np.intp),
                   np.zeros(0), np.zeros((0, 2)))

    @classmethod
    def concatenate(cls, parts: list) -> "Events":
        """One Events of all parts, in canonical (time, kind, i, j) order (a single part already
        in that order is returned as it is)."""
        if not parts:
            return cls.empty()
        merged = parts[0] if len(parts) == 1 else cls(*(np.concatenate([getattr(p, name) for p in parts])
                                                        for name in _EVENT_FIELDS))
        if merged.in_order():   # (the blocks of a run, or the support a world asleep logs a step)
            return merged
        return merged.take(canonical_order(merged.time, merged.kind, merged.i, merged.j))

    def in_order(self) -> bool:
        """Are the events in canonical (time, kind, i, j) order? (The stable sort would then give
        them as they are; checking costs less than sorting.)"""
        ahead = np.zeros(max(len(self.time) - 1, 0), np.bool_)   # a key past the one before
        tied = np.ones_like(ahead)                               # every key so far equal to it
        for name in ("time", "kind", "i", "j"):
            key = getattr(self, name)
            before, after = key[:-1], key[1:]
            ahead |= tied & (after > before)
            tied &= after == before
            if not np.all(ahead | tied):
                return False
        return True

    def take(self, index) -> "Events":
        return Events(*(getattr(self, name)[index] for name in _EVENT_FIELDS))

    def between(self, start: float, end: float) -> "Events":
        """The events with start < time <= end, as views: found by bisection, since events are
        kept in canonical order, time first (a player asks this every frame, of a block that
        may hold a hundred thousand events)."""
        first, last = np.searchsorted(self.time, [start, end], side="right")
        return self.take(slice(first, last))

    def __len__(self) -> int:
        return len(self.time)


MAX_EVENTS = 10_000_000   # events a run keeps (about 500 MB); the per-frame counts are always complete


def _with_room(array, size: int, used: int):
    """`array` if it has `size` rows, else a copy with room for max(size, twice as many) holding
    its first `used` (arrays.grown in numpy: called from Python, the compiled one would compile a
    copy with Python's wrappers for each of the events' four dtypes on a first run)."""
    if size <= len(array):
        return array
    bigger = np.empty((max(size, 2 * len(array)),) + array.shape[1:], array.dtype)
    bigger[:used] = array[:used]
    return bigger


class PastEvents:
    """A run's events so far, grown block by block as a player plays a stream: what the
    Trajectory of the whole run would hold in `events` (its first MAX_EVENTS), read up to a
    time. Blocks come in time order, each in canonical order, so appending keeps the order."""

    def __init__(self, cap: int = MAX_EVENTS):
        self.cap, self.size = cap, 0
        self._arrays = Events.empty()

    def add(self, events: Events) -> None:
        count = min(len(events), self.cap - self.size)
        if count <= 0:
            return
        if self.size + count > len(self._arrays):   # room for at least twice as many (arrays.grown)
            self._arrays = Events(*(_with_room(getattr(self._arrays, name), self.size + count, self.size)
                                    for name in _EVENT_FIELDS))
        for name in _EVENT_FIELDS:
            getattr(self._arrays, name)[self.size:self.size + count] = getattr(events, name)[:count]
        self.size += count

    def up_to(self, time: float) -> Events:
        """The events with time <= `time`, as views."""
        kept = self._arrays.take(slice(0, self.size))
        return kept.take(slice(0, int(np.searchsorted(kept.time, time, side="right"))))


@dataclass
class Trajectory:
    """The state at every frame time t = 0, 1/fps, ..., seconds (F = frames + 1 samples).

    times: (F,)
    positions, velocities: (F, n, 2)
    angles, angular_velocities: (F, n)
    wall_collisions, pair_collisions, segment_collisions: (F,)  collisions in the interval
                       ending at each frame (0 at t = 0)
    candidates: (F,)   broad-phase candidate pairs of the last step of each frame
    approximate: (F,) bool  frames the method could not finish exactly (ccd over its event
                       budget: finished by an approximate step; discrete holding a heavy body up
                       from below, response/hold.py); False everywhere else
    hierarchy: (F, 4)  the slides' funnel at each frame's state: how many pairs pass each of
                       LEVELS in turn (bounding circles, boxes, oriented boxes overlap; the shapes
                       touch), so column 3 counts the pairs truly touching and
                       narrowphase.hierarchy.false_positive_rates reads each level's false
                       positives. NOT_COUNTED (-1) where nothing counted: worlds of circles (every
                       level is the bounding circle's), ccd, pymunk, files written before it
    events: every collision, for pressure, flashes and measurements
    world: the initial World (shapes, masses, colours, box, segments: what a player draws)
    fps, method, broadphase, substeps: how it was simulated
    profile: seconds spent per phase of the step (see engine/profile.py)
    warnings: what the engine had to say about the run
    storage: how the frames were kept (simulate's storage=): "float64"; "float32"; "positions":
             positions and angles as float32, velocities and angular velocities not kept
             (read-only NaN views)
    """
    times: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray
    angles: np.ndarray
    angular_velocities: np.ndarray
    wall_collisions: np.ndarray
    pair_collisions: np.ndarray
    segment_collisions: np.ndarray
    candidates: np.ndarray
    approximate: np.ndarray
    world: World
    fps: float
    events: Events = field(default_factory=Events.empty)
    method: str = "discrete"
    broadphase: str = ""
    substeps: int = 1
    profile: dict = field(default_factory=dict)
    warnings: list = field(default_factory=list)
    storage: str = "float64"
    hierarchy: np.ndarray = None

    # how Jupyter shows a run: a short video, which the model cannot make; notebook.py sets it
    preview_html = None

    def _repr_html_(self):
        return None if Trajectory.preview_html is None else Trajectory.preview_html(self)

    def __post_init__(self):
        if self.hierarchy is None:   # made by a method that does not count (pymunk's trajectories)
            self.hierarchy = np.broadcast_to(np.int64(NOT_COUNTED), (len(self.times), len(LEVELS)))

    @property
    def frames(self) -> int:
        return len(self.times) - 1

    @property
    def radii(self) -> np.ndarray:
        return self.world.radii

    @property
    def masses(self) -> np.ndarray:
        return self.world.masses

    @property
    def collisions(self) -> np.ndarray:
        """Collisions of every kind per frame: (F,)."""
        return self.wall_collisions + self.pair_collisions + self.segment_collisions

    def kinetic_energy(self) -> np.ndarray:
        """(F,) total kinetic energy at each frame (translation and rotation)."""
        self._need_velocities("kinetic energy")
        translation = 0.5 * np.einsum("n,fnk,fnk->f", self.masses, self.velocities, self.velocities)
        return translation + 0.5 * np.einsum("n,fn,fn->f", self.world.inertias, self.angular_velocities,
                                             self.angular_velocities)

    def momentum(self) -> np.ndarray:
        """(F, 2) total momentum at each frame."""
        self._need_velocities("momentum")
        return np.einsum("n,fnk->fk", self.masses, self.velocities)

    def _need_velocities(self, what: str) -> None:
        if self.storage == "positions":
            raise ValueError(f"no {what}: this trajectory was simulated with storage='positions', "
                             f"which keeps no velocities")

    def save(self, path) -> Path:
        """Write the trajectory to an .npz file (under a temporary name, renamed when complete)."""
        path = Path(path)
        arrays = {f"frame_{name}": getattr(self, name) for name in _FRAME_FIELDS}
        arrays.update({f"event_{name}": getattr(self.events, name) for name in _EVENT_FIELDS})
        arrays.update({f"world_{name}": getattr(self.world, name) for name in _WORLD_FIELDS})
        arrays.update(world_vertex_start=self.world.vertex_start, world_body_vertices=self.world.body_vertices)
        if not np.all(np.isnan(self.world.capsule_radii)):   # files without capsules keep their bytes
            arrays.update(world_capsule_radii=self.world.capsule_radii)
        if self.world.map is not None:
            arrays.update({f"map_{name}": value for name, value in self.world.map.to_arrays().items()})
        meta = dict(format=FILE_FORMAT, friction=self.world.friction, damping=self.world.damping, fps=self.fps, method=self.method,
                    broadphase=self.broadphase,
                    substeps=self.substeps, restitution=self.world.restitution, profile=self.profile,
                    warnings=[str(w) for w in self.warnings], storage=self.storage)
        arrays["meta"] = np.array(json.dumps(meta))
        with written_whole(path, "trajectory") as temporary, open(temporary, "wb") as file:
            np.savez_compressed(file, **arrays)
        return path


def approximate_summary(approximate: int, frames: int, name: str, reasons: list) -> str:
    """One line: how many frames of a run are approximate (Trajectory.approximate), and why."""
    why = f": {reasons[0]}" if reasons else ""
    return f"{approximate} of {frames} frames of {name} are approximate (Trajectory.approximate){why}"


def load_trajectory(path) -> Trajectory:
    """Read a file written by Trajectory.save. A missing, broken or foreign file, or one of
    another format version, raises ValueError with one line."""
    path = Path(path)
    try:   # the file opened here, not by np.load, which leaves it open when the archive is broken
        with open(path, "rb") as file, np.load(file, allow_pickle=False) as data:
            meta = json.loads(str(data["meta"]))
            arrays = {key: data[key] for key in data.files if key != "meta"}
    except FileNotFoundError:
        raise ValueError(f"cannot read trajectory {path}: not found") from None
    except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile, TypeError):
        raise ValueError(f"cannot read trajectory {path}: not a collisim trajectory file") from None
    if not isinstance(meta, dict) or meta.get("format") != FILE_FORMAT:
        version = meta.get("format") if isinstance(meta, dict) else None
        raise ValueError(f"trajectory file {path} has format version {version}; "
                         f"this collisim reads version {FILE_FORMAT}")
    try:
        world = World(**{name: arrays[f"world_{name}"] for name in _WORLD_FIELDS}, restitution=meta["restitution"],
                      map=_embedded_map(arrays, path), polygons=_polygons(arrays),
                      friction=meta.get("friction", 0.0), damping=meta.get("damping", 1.0))
        events = Events(*(arrays[f"event_{name}"] for name in _EVENT_FIELDS))
        frames = {name: arrays[f"frame_{name}"] for name in _FRAME_FIELDS if name != "hierarchy"}
        frames["hierarchy"] = arrays.get("frame_hierarchy")   # None in files from before it: NOT_COUNTED
        problem = _disagreement(frames, events, world.n)
        if problem:
            raise ValueError(f"cannot read trajectory {path}: its arrays disagree ({problem})")
        return Trajectory(**frames, world=world, fps=float(meta["fps"]), events=events, method=meta["method"],
                          broadphase=meta["broadphase"], substeps=int(meta["substeps"]), profile=meta["profile"],
                          warnings=list(meta["warnings"]), storage=meta.get("storage", "float64"))
    except KeyError:
        raise ValueError(f"cannot read trajectory {path}: not a collisim trajectory file") from None


def _disagreement(frames: dict, events: Events, n: int) -> str:
    """The first array of a file whose shape does not fit its frame count and n bodies (or whose
    events name a body that is not there), or ''."""
    count = len(frames["times"])
    per_body = {"positions": (count, n, 2), "velocities": (count, n, 2), "angles": (count, n),
                "angular_velocities": (count, n)}
    for name in _FRAME_FIELDS:
        value = frames[name]
        shape = per_body.get(name, (count, len(LEVELS)) if name == "hierarchy" else (count,))
        if value is not None and value.shape != shape:
            return f"{name} has shape {value.shape}, not {shape}"
    k = len(events.time)
    for name in _EVENT_FIELDS:
        value = getattr(events, name)
        shape = (k, 2) if name == "point" else (k,)
        if value.shape != shape:
            return f"event {name} has shape {value.shape}, not {shape}"
    if k and not (0 <= events.i.min() and events.i.max() < n):
        return f"events name bodies outside 0..{n - 1}"
    return ""


def _embedded_map(arrays: dict, path):
    """The collision map saved with the trajectory's world, or None."""
    fields = {key[len("map_"):]: value for key, value in arrays.items() if key.startswith("map_")}
    if not fields:
        return None
    return StaticMap.kinds["CollisionMap"].from_arrays(fields, path)


def _polygons(arrays) -> list | None:
    """The World's shapes argument from a file's vertex table and capsule radii (None for files
    of circles)."""
    if "world_vertex_start" not in arrays:
        return None
    return polygons_of(arrays["world_vertex_start"], arrays["world_body_vertices"], arrays.get("world_capsule_radii"))
