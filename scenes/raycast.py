"""Ray queries: a sensor sweeping rays through the 250-particle gas, each hit with its point and normal, and a fast missile that a ray of its own step never lets through."""
import numpy as np

import collisim
from collisim import palette
from collisim.gas import lattice_gas
from collisim.render import raster
from collisim.render.explain import Caption, Explainer

BOX = (0.0, 0.0, 32.0, 18.0)
SENSOR = np.array([16.0, 9.0])
RAYS = 48
REACH = 11.0                 # how far the sensor sees
TURN = 0.35                  # radians per second the fan of rays turns
NORMAL_LENGTH = 0.6
MISSILE_SPEED = 75.0         # world units a second: 1.25 a frame, several radii of the smallest particle
LAUNCH_EVERY = 1.5           # seconds


def gas_world() -> collisim.World:
    positions, velocities, radii = lattice_gas(250, box=BOX, speed=3.0, seed=7)
    return collisim.World(positions=positions, velocities=velocities, radii=radii, box=BOX)


def missile_path(launch: int):
    """Launch k: (start time, start point, velocity): from the left wall at a height and angle
    that vary from launch to launch, toward the right."""
    rng = np.random.default_rng(launch)
    height = rng.uniform(2.0, 16.0)
    angle = rng.uniform(-0.25, 0.25)
    return launch * LAUNCH_EVERY, np.array([BOX[0] + 0.05, height]), MISSILE_SPEED * np.array([np.cos(angle),
                                                                                               np.sin(angle)])


def sensor_fan(time: float) -> np.ndarray:
    """(RAYS, 2) unit directions of the sensor's rays at `time`."""
    angles = TURN * time + np.linspace(0.0, 2.0 * np.pi, RAYS, endpoint=False)
    return np.column_stack([np.cos(angles), np.sin(angles)])


class RaysOverlay:
    """Draws the sensor's rays and the missile. Every ray is a query against the frame's
    recorded positions (collisim.raycast_many); nothing here moves a particle. The missile is
    not a body: each frame it asks for the first particle on the segment it covers this frame,
    so it cannot pass through one however fast it flies."""

    def __init__(self, world: collisim.World, fps: float):
        self.world, self.dt = world, 1.0 / fps

    def __call__(self, canvas, view, state):
        world = self.world
        directions = sensor_fan(state.time)
        origins = np.repeat(SENSOR[None], RAYS, axis=0)
        found = collisim.raycast_many(world, origins, directions, REACH, positions=state.positions)
        hit = np.isfinite(found.distance)
        ends = np.where(hit[:, None], found.points, origins + REACH * directions)
        raster.draw_lines(canvas, view, origins[~hit], ends[~hit], palette.DIM_TEXT, 1)
        raster.draw_lines(canvas, view, origins[hit], ends[hit], palette.HIGHLIGHT, 1)
        raster.draw_lines(canvas, view, found.points[hit], found.points[hit] + NORMAL_LENGTH * found.normals[hit],
                          palette.TEXT, 1)
        raster.draw_rings(canvas, view.to_pixels(found.points[hit]), np.full(hit.sum(), 2.5), palette.HIGHLIGHT, 1)
        raster.draw_rings(canvas, view.to_pixels(SENSOR[None]), [6.0], palette.TEXT, 2)
        self._missile(canvas, view, state)

    def _missile(self, canvas, view, state):
        launch = int(state.time // LAUNCH_EVERY)
        start_time, start, velocity = missile_path(launch)
        hits = state.memory.setdefault("missile hits", {})   # launch -> (time, point, normal) of its first hit
        if launch not in hits and state.time > start_time:
            # the ray of the step that ended now: from where the missile was one frame ago
            before = start + velocity * max(state.time - self.dt - start_time, 0.0)
            step = velocity * (state.time - start_time) - (before - start)
            hit = collisim.raycast(self.world, before, step, float(np.hypot(*step)), positions=state.positions)
            if hit is not None and hit.kind == "body":
                hits[launch] = (state.time, hit.point, hit.normal)
        if launch in hits:
            when, point, normal = hits[launch]
            age = state.time - when
            raster.draw_rings(canvas, view.to_pixels(point[None]), [4.0 + 40.0 * age], palette.FLASH, 2)
            raster.draw_lines(canvas, view, [point], [point + 1.5 * normal], palette.FLASH, 2)
            label = f"missile {launch + 1}: hit at ({point[0]:.2f}, {point[1]:.2f}), normal ({normal[0]:.2f}, {normal[1]:.2f})"
        else:
            position = start + velocity * (state.time - start_time)
            raster.draw_lines(canvas, view, [position - velocity * self.dt], [position], palette.FLASH, 3)
            label = f"missile {launch + 1}: {MISSILE_SPEED * self.dt:.2f} units a frame, ray of one step ahead"
        state.memory["missile status"] = label   # shown in the caption strip above the gas (render/explain.py)


def scene() -> collisim.Scene:
    world, fps = gas_world(), 60
    status = Explainer([Caption(lambda state: state.memory.get("missile status", ""), 0.0, None, "top")], lines=1)
    settings = collisim.RenderSettings(overlay=RaysOverlay(world, fps), explainer=status, flash=False)
    return collisim.Scene(world=world, fps=fps, seconds=9.0, method="discrete", render=settings)
