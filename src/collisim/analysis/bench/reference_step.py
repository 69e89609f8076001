"""A minimal compiled discrete step: the yardstick of `collisim bench broadphase`.

Not part of the engine. It answers "how fast can a plain compiled step of this gas be?", so that
collisim's whole discrete step is judged against a yardstick and not only against pymunk. It does
the least a correct discrete step of a gas of circles in a box must do, in one compiled loop:

1. move: x += v·dt for every particle;
2. bin: a counting sort into a uniform grid of cells at least a diameter of the largest circle
   wide, and every particle's data (x, y, vx, vy, r, 1/m, id) *gathered* into cell order, so
   the pair loop reads neighbours from contiguous memory;
3. pairs: for each cell, the pairs inside it and with the half 3×3 neighbourhood (east,
   north-west, north, north-east: each pair of neighbouring cells once); a pair that touches
   and approaches gets the elastic impulse along the line of centres, and any touching pair is
   pushed apart along it, split by inverse mass (positions only);
4. walls: a particle past a wall is reflected back inside (its position mirrored, its normal
   velocity turned inward), so every particle ends the step in the box.

Not done, unlike collisim's step: constant accelerations, restitution other than 1, segments,
maps, shapes other than circles, event logs, per-frame recording, statistics, profiling.
The data stays in cell order between steps (`ids` says which particle is where); `positions`
and `velocities` put it back in the World's order.
"""
from __future__ import annotations

import numpy as np
from numba import njit


class ReferenceStep:
    """A gas of circles in a box advanced by the minimal step (see the module docstring)."""

    def __init__(self, positions, velocities, radii, masses, box, dt: float):
        positions, velocities = np.asarray(positions, np.float64), np.asarray(velocities, np.float64)
        n = len(positions)
        self.box = np.asarray(box, np.float64)
        self.dt = float(dt)
        xmin, ymin, xmax, ymax = self.box
        reach = 2.0 * float(np.max(radii)) if n else 1.0      # cells at least a diameter wide
        self.nx = max(1, int((xmax - xmin) // reach))
        self.ny = max(1, int((ymax - ymin) // reach))
        self.cell_w, self.cell_h = (xmax - xmin) / self.nx, (ymax - ymin) / self.ny
        self.data = _columns(positions, velocities, radii, masses)   # x, y, vx, vy, r, 1/m, id
        self.spare = tuple(np.empty_like(column) for column in self.data)
        self.cell_of = np.empty(n, np.int64)
        self.start = np.empty(self.nx * self.ny + 1, np.int64)

    @classmethod
    def from_world(cls, world, fps: float) -> "ReferenceStep":
        return cls(world.positions, world.velocities, world.radii, world.masses, world.box, 1.0 / fps)

    def run(self, steps: int) -> None:
        """Advance `steps` steps of dt."""
        swapped = reference_steps(*self.data, *self.spare, self.cell_of, self.start, self.box,
                                  self.cell_w, self.cell_h, self.nx, self.ny, self.dt, int(steps))
        if swapped:
            self.data, self.spare = self.spare, self.data

    @property
    def positions(self) -> np.ndarray:
        """(n, 2) in the World's order."""
        x, y, _, _, _, _, ids = self.data
        return _in_world_order(x, y, ids)

    @property
    def velocities(self) -> np.ndarray:
        """(n, 2) in the World's order."""
        _, _, vx, vy, _, _, ids = self.data
        return _in_world_order(vx, vy, ids)

    def kinetic_energy(self) -> float:
        _, _, vx, vy, _, inverse_mass, _ = self.data
        return float(np.sum(0.5 * (vx ** 2 + vy ** 2) / inverse_mass))


def _columns(positions, velocities, radii, masses) -> tuple:
    n = len(positions)
    radii = np.broadcast_to(np.asarray(radii, np.float64), (n,))
    masses = np.broadcast_to(np.asarray(masses, np.float64), (n,))
    return (positions[:, 0].copy(), positions[:, 1].copy(), velocities[:, 0].copy(), velocities[:, 1].copy(),
            radii.copy(), 1.0 / masses, np.arange(n, dtype=np.float64))


@njit(cache=True)
def reference_steps(x, y, vx, vy, r, im, ids, x2, y2, vx2, vy2, r2, im2, ids2,
                    cell_of, start, box, cell_w, cell_h, nx, ny, dt, steps):
    """Advance `steps` steps. Each step gathers the data from the first set of columns into
    the second in cell order and works there; the sets then trade places. Returns True when
    the data ends in the second set (an odd number of steps)."""
    for _ in range(steps):
        move(x, y, vx, vy, dt)
        gather(x, y, vx, vy, r, im, ids, x2, y2, vx2, vy2, r2, im2, ids2,
               cell_of, start, box, cell_w, cell_h, nx, ny)
        collide_pairs(x2, y2, vx2, vy2, r2, im2, start, nx, ny)
        reflect_walls(x2, y2, vx2, vy2, r2, box)
        x, y, vx, vy, r, im, ids, x2, y2, vx2, vy2, r2, im2, ids2 = \
            x2, y2, vx2, vy2, r2, im2, ids2, x, y, vx, vy, r, im, ids
    return steps % 2 == 1


@njit(cache=True)
def move(x, y, vx, vy, dt):
    for i in range(len(x)):
        x[i] += vx[i] * dt
        y[i] += vy[i] * dt


@njit(cache=True)
def gather(x, y, vx, vy, r, im, ids, x2, y2, vx2, vy2, r2, im2, ids2,
           cell_of, start, box, cell_w, cell_h, nx, ny):
    """Counting sort by cell; start[c]:start[c + 1] are cell c's particles afterwards."""
    n = len(x)
    start[:] = 0
    for i in range(n):
        cx = min(max(int((x[i] - box[0]) / cell_w), 0), nx - 1)
        cy = min(max(int((y[i] - box[1]) / cell_h), 0), ny - 1)
        c = cy * nx + cx
        cell_of[i] = c
        start[c + 1] += 1
    for c in range(nx * ny):
        start[c + 1] += start[c]
    for i in range(n):                    # start[c] runs ahead while cell c fills...
        k = start[cell_of[i]]
        start[cell_of[i]] = k + 1
        x2[k], y2[k], vx2[k], vy2[k] = x[i], y[i], vx[i], vy[i]
        r2[k], im2[k], ids2[k] = r[i], im[i], ids[i]
    for c in range(nx * ny, 0, -1):       # ...and now stands at cell c + 1's start: shift back
        start[c] = start[c - 1]
    start[0] = 0


@njit(cache=True)
def collide_pairs(x, y, vx, vy, r, im, start, nx, ny):
    """Every touching pair once: inside each cell, and with its E, NW, N and NE neighbours."""
    for cy in range(ny):
        for cx in range(nx):
            c = cy * nx + cx
            for a in range(start[c], start[c + 1]):
                for b in range(a + 1, start[c + 1]):
                    resolve(a, b, x, y, vx, vy, r, im)
                for dx, dy in ((1, 0), (-1, 1), (0, 1), (1, 1)):
                    ox, oy = cx + dx, cy + dy
                    if 0 <= ox < nx and oy < ny:
                        o = oy * nx + ox
                        for b in range(start[o], start[o + 1]):
                            resolve(a, b, x, y, vx, vy, r, im)


@njit(cache=True)
def resolve(a, b, x, y, vx, vy, r, im):
    """If a and b touch: the elastic impulse when they approach, and push them apart."""
    dx, dy = x[b] - x[a], y[b] - y[a]
    reach = r[a] + r[b]
    d2 = dx * dx + dy * dy
    if d2 >= reach * reach or d2 == 0.0:
        return
    d = np.sqrt(d2)
    ux, uy = dx / d, dy / d
    w = im[a] + im[b]
    closing = (vx[b] - vx[a]) * ux + (vy[b] - vy[a]) * uy
    if closing < 0.0:
        j = -2.0 * closing / w            # e = 1: the normal relative velocity reverses
        vx[a] -= j * im[a] * ux
        vy[a] -= j * im[a] * uy
        vx[b] += j * im[b] * ux
        vy[b] += j * im[b] * uy
    push = (reach - d) / w
    x[a] -= push * im[a] * ux
    y[a] -= push * im[a] * uy
    x[b] += push * im[b] * ux
    y[b] += push * im[b] * uy


@njit(cache=True)
def reflect_walls(x, y, vx, vy, r, box):
    for i in range(len(x)):
        x[i], vx[i] = reflect(x[i], vx[i], box[0] + r[i], box[2] - r[i])
        y[i], vy[i] = reflect(y[i], vy[i], box[1] + r[i], box[3] - r[i])


@njit(cache=True)
def reflect(p, v, low, high):
    """A coordinate and its velocity kept in [low, high]: mirrored at the wall it passed."""
    if p < low:
        p, v = min(2.0 * low - p, high), abs(v)
    elif p > high:
        p, v = max(2.0 * high - p, low), -abs(v)
    return p, v


def _in_world_order(a: np.ndarray, b: np.ndarray, ids: np.ndarray) -> np.ndarray:
    """Columns a, b (n,) kept in cell order, as (n, 2) rows in the World's order (ids: each row's body)."""
    out = np.empty((len(a), 2))
    order = ids.astype(np.intp)
    out[order, 0], out[order, 1] = a, b
    return out
