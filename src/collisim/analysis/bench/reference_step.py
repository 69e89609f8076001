"""The minimal compiled step: the yardstick of `collisim bench broadphase`.

Not part of the engine. It answers "how fast can a plain compiled step of this gas be?", so that
collisim's step is judged against a yardstick and not only against pymunk. It is one compiled
function, written as the loop anyone would write first, doing the least a discrete step of an
elastic gas of circles in a box must do:

1. move every body by v·dt and reflect it at the walls it passed (position mirrored, normal
   velocity turned inward);
2. a counting sort of the bodies into a grid of cells at least the largest diameter wide, each
   body's row (x, y, vx, vy, r, 1/m, id) copied into cell order: the pair loop then reads
   neighbours from contiguous memory, and the data stays in cell order between steps;
3. for each cell, its bodies against the rest of the cell and its half 3×3 stencil (east, and
   north-west, north, north-east: each pair of neighbouring cells once). In cell order the cell
   and its east neighbour are one run of rows, and the three northern cells another;
4. a pair that touches and approaches gets the elastic impulse along its line of centres.

Nothing else: no push-apart of overlaps, no accelerations, restitution 1 only, no segments,
maps, polygons, event logs or recording. Positions change only in 1, so the touching pairs a
step finds are the touching pairs of its final positions (what the tests check by brute force).
"""
from __future__ import annotations

import numpy as np
from numba import njit

X, Y, VX, VY, R, INV_M, ID = range(7)     # the columns of a body's row


class MinimalStep:
    """A gas of circles in a box advanced by the minimal step (see the module docstring)."""

    def __init__(self, positions, velocities, radii, masses, box, dt: float):
        positions = np.asarray(positions, np.float64).reshape(-1, 2)
        n = len(positions)
        self.bodies = np.empty((n, 7))
        self.bodies[:, [X, Y]] = positions
        self.bodies[:, [VX, VY]] = velocities
        self.bodies[:, R] = radii
        self.bodies[:, INV_M] = 1.0 / np.broadcast_to(np.asarray(masses, np.float64), (n,))
        self.bodies[:, ID] = np.arange(n)
        self.spare = np.empty_like(self.bodies)
        self.box = np.asarray(box, np.float64)
        self.dt = float(dt)
        width, height = self.box[2] - self.box[0], self.box[3] - self.box[1]
        diameter = 2.0 * float(self.bodies[:, R].max()) if n else 1.0
        self.nx, self.ny = max(1, int(width // diameter)), max(1, int(height // diameter))
        self.cell_w, self.cell_h = width / self.nx, height / self.ny
        self.cell_of = np.empty(n, np.int64)
        self.start = np.empty(self.nx * self.ny + 1, np.int64)
        self.touching = 0        # touching pairs the last step found

    @classmethod
    def from_world(cls, world, fps: float) -> "MinimalStep":
        return cls(world.positions, world.velocities, world.radii, world.masses, world.box, 1.0 / fps)

    def run(self, steps: int) -> None:
        """Advance `steps` steps of dt."""
        self.bodies, self.spare, self.touching = minimal_steps(
            self.bodies, self.spare, self.cell_of, self.start, self.box, self.cell_w, self.cell_h,
            self.nx, self.ny, self.dt, int(steps))

    def _in_world_order(self, columns) -> np.ndarray:
        out = np.empty((len(self.bodies), 2))
        out[self.bodies[:, ID].astype(np.intp)] = self.bodies[:, columns]
        return out

    @property
    def positions(self) -> np.ndarray:
        """(n, 2) in the World's order."""
        return self._in_world_order([X, Y])

    @property
    def velocities(self) -> np.ndarray:
        """(n, 2) in the World's order."""
        return self._in_world_order([VX, VY])

    @property
    def ids(self) -> np.ndarray:
        """Each row's body, in cell order."""
        return self.bodies[:, ID].astype(np.int64)

    def kinetic_energy(self) -> float:
        b = self.bodies
        return float(np.sum(0.5 * (b[:, VX] ** 2 + b[:, VY] ** 2) / b[:, INV_M]))

    def momentum(self) -> np.ndarray:
        b = self.bodies
        return np.array([np.sum(b[:, VX] / b[:, INV_M]), np.sum(b[:, VY] / b[:, INV_M])])


@njit(cache=True)
def minimal_steps(bodies, spare, cell_of, start, box, cell_w, cell_h, nx, ny, dt, steps):
    """Advance `steps` steps: (bodies, spare, touching pairs found in the last step). Each step
    copies the rows from `bodies` into `spare` in cell order, and the two trade places."""
    n = len(bodies)
    touching = 0
    for _ in range(steps):
        # 1. move, and reflect at the walls
        for i in range(n):
            r = bodies[i, R]
            bodies[i, X] += bodies[i, VX] * dt
            bodies[i, Y] += bodies[i, VY] * dt
            if bodies[i, X] < box[0] + r:
                bodies[i, X] = min(2.0 * (box[0] + r) - bodies[i, X], box[2] - r)
                bodies[i, VX] = abs(bodies[i, VX])
            elif bodies[i, X] > box[2] - r:
                bodies[i, X] = max(2.0 * (box[2] - r) - bodies[i, X], box[0] + r)
                bodies[i, VX] = -abs(bodies[i, VX])
            if bodies[i, Y] < box[1] + r:
                bodies[i, Y] = min(2.0 * (box[1] + r) - bodies[i, Y], box[3] - r)
                bodies[i, VY] = abs(bodies[i, VY])
            elif bodies[i, Y] > box[3] - r:
                bodies[i, Y] = max(2.0 * (box[3] - r) - bodies[i, Y], box[1] + r)
                bodies[i, VY] = -abs(bodies[i, VY])
        # 2. counting sort: start[c + 1] counts cell c, then start[c] is where cell c begins
        start[:] = 0
        for i in range(n):
            cx = min(int((bodies[i, X] - box[0]) / cell_w), nx - 1)
            cy = min(int((bodies[i, Y] - box[1]) / cell_h), ny - 1)
            cell_of[i] = cy * nx + cx
            start[cell_of[i] + 1] += 1
        for c in range(nx * ny):
            start[c + 1] += start[c]
        for i in range(n):            # start[c] runs ahead as cell c fills...
            k = start[cell_of[i]]
            start[cell_of[i]] = k + 1
            spare[k, :] = bodies[i, :]
        for c in range(nx * ny, 0, -1):   # ...and ends at cell c + 1's start: shift it back
            start[c] = start[c - 1]
        start[0] = 0
        bodies, spare = spare, bodies
        # 3. pairs: the rest of the cell and its east neighbour, then the three cells north
        touching = 0
        for cy in range(ny):
            for cx in range(nx):
                c = cy * nx + cx
                east_end = start[c + 2] if cx + 1 < nx else start[c + 1]
                north_lo = c + nx - 1 if cx > 0 else c + nx
                north_hi = c + nx + 1 if cx + 1 < nx else c + nx
                for a in range(start[c], start[c + 1]):
                    for b in range(a + 1, east_end):
                        touching += bounce(bodies, a, b)
                    if cy + 1 < ny:
                        for b in range(start[north_lo], start[north_hi + 1]):
                            touching += bounce(bodies, a, b)
    return bodies, spare, touching


@njit(cache=True)
def bounce(bodies, a, b):
    """1 if rows a and b touch (and then, if they approach, the elastic impulse), else 0."""
    dx, dy = bodies[b, X] - bodies[a, X], bodies[b, Y] - bodies[a, Y]
    reach = bodies[a, R] + bodies[b, R]
    d2 = dx * dx + dy * dy
    if d2 >= reach * reach:
        return 0
    closing = (bodies[b, VX] - bodies[a, VX]) * dx + (bodies[b, VY] - bodies[a, VY]) * dy
    if closing < 0.0:
        k = -2.0 * closing / (d2 * (bodies[a, INV_M] + bodies[b, INV_M]))   # e = 1: the normal velocity reverses
        bodies[a, VX] -= k * bodies[a, INV_M] * dx
        bodies[a, VY] -= k * bodies[a, INV_M] * dy
        bodies[b, VX] += k * bodies[b, INV_M] * dx
        bodies[b, VY] += k * bodies[b, INV_M] * dy
    return 1
