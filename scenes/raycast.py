"""Ray queries: a sensor sweeping rays through a gas of 250 particles, discs and polygons, each hit with its point and normal, and a fast missile that a ray of its own step never lets through."""
import numpy as np

import collisim
from collisim import palette
from collisim.gas import lattice_gas
from collisim.render import raster
from collisim.render.explain import Caption, Explainer
from collisim.shapes import box, regular

BOX = (0.0, 0.0, 32.0, 18.0)
SENSOR = np.array([16.0, 9.0])
RAYS = 48
REACH = 11.0                 # how far the sensor sees
TURN = 0.35                  # radians per second the fan of rays turns
NORMAL_LENGTH = 0.6
POLYGON_EVERY = 2            # one large particle in this many is a polygon: rays hit faces and corners too
MISSILE_SPEED = 75.0         # world units a second: 1.25 a frame, several radii of the smallest particle
LAUNCH_EVERY = 1.5           # seconds


def polygon_of(k: int, radius: float) -> np.ndarray:
    """The k-th polygon of the gas, within a circle of `radius` (its lattice spot): a box, a
    triangle, a pentagon, a hexagon in turn."""
    if k % 4 == 0:
        return box(1.6 * radius, 1.2 * radius)    # half-diagonal = radius
    return regular((3, 5, 6)[k % 4 - 1], radius)


def gas_world() -> collisim.World:
    positions, velocities, radii = lattice_gas(250, box=BOX, speed=3.0, seed=7)
    large = np.flatnonzero(radii == radii.max())[::POLYGON_EVERY]
    polygons = [None] * len(positions)
    for k, i in enumerate(large):
        polygons[i] = polygon_of(k, radii[i])
    spins = np.random.default_rng(8).uniform(-2.0, 2.0, len(positions))
    return collisim.World(positions=positions, velocities=velocities, radii=radii, box=BOX, polygons=polygons,
                          angles=np.linspace(0.0, 7.0, len(positions)), angular_velocities=spins)


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


def missile_hits(world):
    """A counter (RenderSettings.counters) called for every physics step the panel plays,
    whatever the video's frame rate: the missile casts the ray of the step that ended at
    `after` (from where it was at `before`) against the particles where they are now, and the
    first hit of each launch is kept in state.memory["missile hits"] as (time, point, normal,
    particle, inside). A ray that starts inside a particle (the particle moved onto the
    missile during the step) has no surface in front of it: the query says so (inside, normal
    (0, 0)), and that is what is kept."""
    def count(before, after):
        launch = int(after.time // LAUNCH_EVERY)
        start_time, start, velocity = missile_path(launch)
        hits = after.memory.setdefault("missile hits", {})
        if launch in hits or after.time <= start_time:
            return 0
        origin = start + velocity * max(before.time - start_time, 0.0)
        step = velocity * (after.time - start_time) - (origin - start)
        hit = collisim.raycast(world, origin, step, float(np.hypot(*step)), positions=after.positions,
                               angles=after.angles)
        if hit is None or hit.kind != "body":
            return 0
        hits[launch] = (after.time, hit.point, hit.normal, hit.index, hit.inside)
        return 1
    return count


class RaysOverlay:
    """Draws the sensor's rays and the missile. Every ray is a query against the frame's
    recorded positions (collisim.raycast_many); nothing here moves a particle. The missile is
    not a body: each physics step it asks for the first particle on the segment it covers in
    that step (missile_hits), so it cannot pass through one however fast it flies."""

    def __init__(self, world: collisim.World, fps: float):
        self.world, self.dt = world, 1.0 / fps

    def __call__(self, canvas, view, state):
        origins, directions, found, _ = sensor_rays(self.world, state)
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
        hits = state.memory.get("missile hits", {})
        if launch in hits:
            when, point, normal, particle, inside = hits[launch]
            age = state.time - when
            raster.draw_rings(canvas, view.to_pixels(point[None]), [4.0 + 40.0 * age], palette.FLASH, 2)
            if not inside:
                raster.draw_lines(canvas, view, [point], [point + 1.5 * normal], palette.FLASH, 2)
        else:
            position = start + velocity * (state.time - start_time)
            tail = start + velocity * max(state.time - self.dt - start_time, 0.0)   # from the wall, never behind it
            raster.draw_lines(canvas, view, [tail], [position], palette.FLASH, 3)


def sensor_rays(world, state):
    """The sensor's rays at this sample: where each starts, its direction, the query's RayHits
    and the particle the sensor sits in (-1 for none), asked once a sample (the overlay draws
    them, a caption counts them). Particles drift over the sensor; its rays look past the one
    that holds it (skip_inside, Box2D's rule) and report what lies beyond."""
    kept = state.memory.get("sensor")
    if kept is None or kept[0] != state.sample:
        directions = sensor_fan(state.time)
        starts = np.repeat(SENSOR[None], RAYS, axis=0)
        found = collisim.raycast_many(world, starts, directions, REACH, positions=state.positions,
                                      angles=state.angles, skip_inside=True)
        here = collisim.raycast(world, SENSOR, (1.0, 0.0), 0.0, positions=state.positions, angles=state.angles)
        holder = here.index if here is not None and here.inside and here.kind == "body" else -1
        kept = state.memory["sensor"] = (state.sample, starts, directions, found, holder)
    return kept[1:]


def sensor_status(world):
    """The query's own answers this frame: how many rays hit a particle or a wall, and how many
    particles the broad phase handed to the exact test."""
    def text(state):
        _, _, found, holder = sensor_rays(world, state)
        bodies = int(np.sum(found.kinds == found.KIND_NAMES.index("body")))
        walls = int(np.sum(found.kinds == found.KIND_NAMES.index("wall")))
        inside = f"in particle {holder}, looking past it: " if holder >= 0 else ""
        return (f"sensor {inside}of {RAYS} rays, {bodies} hit a particle, {walls} a wall; "
                f"exact tests {int(found.tested.sum())} of {RAYS * world.n}")
    return text


def sensor_example(world):
    """The point and normal of the sensor's first ray that hits a particle, as the query gives them."""
    def text(state):
        _, _, found, _ = sensor_rays(world, state)
        bodies = np.flatnonzero(found.kinds == found.KIND_NAMES.index("body"))
        title = "a ray query returns the point it hits and the surface normal there"
        if not len(bodies):
            return title
        point, normal = found.points[bodies[0]], found.normals[bodies[0]]
        return (f"{title}: ray {bodies[0] + 1} at ({point[0]:.2f}, {point[1]:.2f}), "
                f"normal ({normal[0]:.2f}, {normal[1]:.2f})")
    return text


def missile_status(state, dt: float) -> str:
    """What the current launch's missile has found so far, in the query's words."""
    launch = int(state.time // LAUNCH_EVERY)
    hits = state.memory.get("missile hits", {})
    if launch not in hits:
        return f"missile {launch + 1}: {MISSILE_SPEED * dt:.2f} units a step, a ray along each step"
    _, point, normal, particle, inside = hits[launch]
    where = f"({point[0]:.2f}, {point[1]:.2f}), normal ({normal[0]:.2f}, {normal[1]:.2f})"
    if inside:
        return f"missile {launch + 1}: particle {particle} moved onto it at ({point[0]:.2f}, {point[1]:.2f})"
    return f"missile {launch + 1}: hit particle {particle} at {where}"


def explainer(world, fps) -> Explainer:
    return Explainer([
        Caption(sensor_example(world), 0.0, None, "top"),
        Caption(sensor_status(world), 0.0, None, "top", 1),
        Caption(lambda state: missile_status(state, 1.0 / fps), 0.0, None, "bottom"),
        Caption(lambda state: f"a step of {MISSILE_SPEED / fps:.2f} > a small particle's width "
                              f"{2 * world.radii.min():.2f}: checked where it lands, it could jump one; "
                              f"hits so far: {state.counters.get('missiles hit', 0)}", 0.0, None, "bottom", 1),
    ])


def scene() -> collisim.Scene:
    world, fps = gas_world(), 60
    settings = collisim.RenderSettings(overlay=RaysOverlay(world, fps), flash=False, explainer=explainer(world, fps),
                                       counters={"missiles hit": missile_hits(world)})
    return collisim.Scene(world=world, fps=fps, seconds=9.0, method="discrete", render=settings)
