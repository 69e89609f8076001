"""Numbers a tutorial scene puts on screen are the engine's, on every frame: each caption that
states a count is checked against the trajectory it is drawn from."""
import re

import numpy as np
import pytest
from shapely.geometry import Point

import collisim
from collisim.render.player import FrameState
from collisim.model.scenefile import available_scenes


@pytest.fixture(scope="module")
def six():
    """The scene file as a module, to call its caption functions."""
    import importlib.util
    spec = importlib.util.spec_from_file_location("broadphase_six_scene", available_scenes()["broadphase_six"])
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def states(trajectory):
    """A FrameState for every sample, as the player builds them (one memory for the whole play)."""
    memory = {}
    for f in range(len(trajectory.times)):
        past = trajectory.events.take(trajectory.events.time <= trajectory.times[f] + 1e-12)
        yield FrameState(float(trajectory.times[f]), f, trajectory.positions[f], trajectory.velocities[f],
                         trajectory.angles[f], int(trajectory.candidates[f]), int(trajectory.pair_collisions[f]),
                         0, 0, past, memory=memory)


def numbers(text):
    return [int(n) for n in re.findall(r"\d+", text)]


def played(six, index):
    """(state, trajectory) at every video frame of chapter `index` of broadphase_six at -ql, the
    states as the player builds them (clock set, frozen frames included), the trajectory the
    engine's own run of that chapter's panel, simulated here apart from the player."""
    from collisim.render.timeline import make_players
    scene = six.scene()
    panel = scene.chapters[index].panels[0]
    trajectory = collisim.simulate(panel.scene)
    job = collisim.pipeline.plan(scene, quality="l")
    chapter = job.chapters[index]
    player = make_players(chapter, job.size, job.fps)[0]
    for frame in range(chapter.frames):
        player.advance(frame)
        player.state.clock = player.clock
        yield player.state, trajectory


def engine_candidates(state, trajectory):
    return int(trajectory.candidates[state.sample])


def test_brute_force_says_it_tests_all_15_pairs_and_counts_the_engines_overlaps(six):
    from collisim.broadphase import describe
    walked = set()
    for state, trajectory in played(six, 0):
        found = numbers(six.brute_caption(state))
        if six.BRUTE.built(state):
            assert found == [15, engine_candidates(state, trajectory)] and 15 == 6 * 5 // 2
            drawn = describe("brute", *six.boxes(state))["pairs"]
            assert len(drawn) == engine_candidates(state, trajectory)     # the lit pairs are the engine's
        elif found:
            assert found[1] == 15
            walked.add(found[0])
    assert walked == set(range(1, 16))      # every pair is shown being tested


def x_overlaps(lo, hi):
    """Pairs whose intervals on x overlap, counted here by brute force."""
    return sum(lo[i, 0] <= hi[j, 0] and lo[j, 0] <= hi[i, 0] for i in range(len(lo)) for j in range(i + 1, len(lo)))


def test_sweep_and_prune_reports_pairs_one_step_at_a_time_up_to_the_engines_count(six):
    """As the video's sweep: every pair whose x intervals meet is reported, more than the two
    whose boxes overlap (the narrow phase sorts them out)."""
    so_far, at_key = [], None
    for state, trajectory in played(six, 1):
        text = six.sweep_caption(state)
        if six.SWEEP.built(state):
            assert numbers(text) == [engine_candidates(state, trajectory), 15]
        elif text:
            so_far.append(numbers(text)[-1])
            at_key = engine_candidates(state, trajectory)
            assert at_key == x_overlaps(*six.boxes(state))
    assert so_far == sorted(so_far) and so_far[-1] == at_key == 4    # grows to the engine's count


def cells_touched(lo, hi, origin, size):
    """Cells (ix, iy) each box overlaps, counted here by brute force."""
    first, last = np.floor((lo - origin) / size).astype(int), np.floor((hi - origin) / size).astype(int)
    return [{(x, y) for x in range(a[0], b[0] + 1) for y in range(a[1], b[1] + 1)} for a, b in zip(first, last)]


def test_the_grid_counts_its_tests_its_memory_and_the_engines_candidates(six):
    grid, checked = six.ENGINE_GRID, 0
    for state, trajectory in played(six, 2):
        if not six.GRID.built(state):
            continue
        tests, candidates, total, memory = numbers(six.grid_caption(state))
        touched = cells_touched(*six.boxes(state), grid.origin, 1.0 / grid.cells_per_unit)
        # the grid tests every pair within each cell (a pair sharing two cells is tested in both)
        in_cell = [sum(cell in cells for cells in touched) for cell in set().union(*touched)]
        assert (tests, candidates, total) == (sum(k * (k - 1) // 2 for k in in_cell),
                                              engine_candidates(state, trajectory), 15)
        assert memory == 8 * (grid.nx * grid.ny + 1) + 8 * sum(len(cells) for cells in touched)
        checked += 1
    assert checked > 0


def test_the_kd_tree_and_the_bvh_count_the_engines_candidates(six):
    from collisim.broadphase import describe
    for index, steps, caption in ((3, six.KD, six.kd_caption), (4, six.BVH, six.bvh_caption)):
        seen = set()
        for state, trajectory in played(six, index):
            text, expected = caption(state), engine_candidates(state, trajectory)
            if steps.live(state) or (steps.built(state) and index == 4):
                assert numbers(text) == [expected, 15]
            elif steps.built(state):
                assert numbers(text)[-1] == expected
            elif text.startswith("split"):
                k, count = numbers(text)[:2]
                assert count == len(describe("kdtree", *six.boxes(state), leaf_size=1)["splits"])
                seen.add(k)
            elif text.startswith("traversal"):
                assert numbers(text)[-1] == expected
                seen.add(numbers(text)[-2])
        assert seen == set(range(1, steps.count + 1)) if index == 3 else seen == {1, 2}


def test_the_narrow_phase_caption_counts_what_the_engine_found_on_every_frame(six):
    touched = 0
    for state, trajectory in played(six, 5):
        found = numbers(six.narrow_caption(state))
        assert found == [trajectory.pair_collisions[state.sample], trajectory.candidates[state.sample]]
        assert len(six.touching_now(state)) == trajectory.pair_collisions[state.sample]
        touched += found[0]
    assert touched > 0   # the scene does show pairs touching
    events = trajectory.events
    assert events.time[events.kind == 1][0] == pytest.approx(six.FIRST_TOUCH)   # the slow motion is around it


def test_tunneling_counts_each_missed_particle_once():
    """A particle that tunnelled through the barrier crosses it again every time it comes back;
    the counter counts particles, so it never exceeds the number of particles."""
    import importlib.util
    spec = importlib.util.spec_from_file_location("tunneling_scene", available_scenes()["tunneling"])
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    world = module.barrier_world()
    trajectory = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=8.0, broadphase="brute"))
    once = module.MissedOnce(module.barrier_crossings)
    every = 0
    total = 0
    frames = list(states(trajectory))
    for before, after in zip(frames, frames[1:]):
        total += once(before, after)
        every += int(module.barrier_crossings(before, after).sum())
    assert 0 < total <= world.n < every     # repeated crossings happen, and are not counted again
    replayed = list(states(trajectory))      # a second play (a still after the video) counts afresh
    assert sum(once(before, after) for before, after in zip(replayed, replayed[1:])) == total


def scene_module(name):
    import importlib.util
    spec = importlib.util.spec_from_file_location(f"{name}_counts", available_scenes()[name])
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def played_scene(scene, quality="l"):
    """The player's state at every video frame of a one-panel scene (clock set)."""
    from collisim.render.timeline import make_players
    job = collisim.pipeline.plan(scene, quality=quality)
    player = make_players(job.chapters[0], job.size, job.fps)[0]
    for frame in range(job.frames):
        player.advance(frame)
        player.state.clock = player.clock
        yield player.state


def test_single_bounce_counts_every_wall_contact_so_far():
    module = scene_module("single_bounce")
    scene = module.scene()
    trajectory = collisim.simulate(scene)
    for state in played_scene(scene):
        assert numbers(module.bounce_count(state)) == [int(trajectory.collisions[:state.sample + 1].sum())]


def test_two_bodies_reads_its_before_and_after_at_the_impact_and_they_conserve():
    """The velocities before and after are the impact's on every later frame (not re-read from
    samples that have moved on): momentum and energy agree to the printed digits."""
    module = scene_module("two_bodies")
    scene = module.scene()
    world = scene.world
    texts = set()
    for state in played_scene(scene):
        if state.clock >= module.PACE.video_time(module.IMPACT) and module.impact(state) is not None:
            texts.add(module.conserved(world)(state))
    assert len(texts) == 1
    momentum_before, momentum_after, energy_before, energy_after = \
        [tuple(map(float, re.findall(r"-?\d+\.\d+", part))) for part in re.split(r"\$\\to\$|energy", texts.pop())]
    assert momentum_before == momentum_after and energy_before == energy_after


def outline(world, positions, angles, i):
    """Body i's outline at a frame as shapely sees it: its circle, or its polygon placed there."""
    from shapely.geometry import Point, Polygon
    if world.shapes[i] == collisim.core.kinds.POLYGON:
        placed = world.placed_vertices(positions, angles)
        return Polygon(placed[world.vertex_start[i]:world.vertex_start[i + 1]])
    return Point(positions[i]).buffer(world.radii[i], 4096)


def test_raycast_missile_hits_a_particles_surface_with_its_normal_at_every_video_rate():
    """The missile's ray covers every physics step whatever the video's rate (at -ql a drawn
    frame is four steps: a ray of one step left three unchecked); each hit shown lies on the
    particle's outline, disc or polygon, at the engine's recorded pose, with a unit normal
    facing the missile (or, where the particle moved onto it, inside with normal (0, 0))."""
    module = scene_module("raycast")
    scene = module.scene()
    trajectory = collisim.simulate(scene)
    found = {}
    for quality in ("l", "h"):
        *_, last = played_scene(scene, quality)
        found[quality] = last.memory["missile hits"]
    assert found["l"].keys() == found["h"].keys() and len(found["l"]) >= 5
    shapes = set()
    for launch, (when, point, normal, particle, inside) in found["l"].items():
        assert found["h"][launch][:1] + found["h"][launch][3:] == (when, particle, inside)
        frame = int(round(when * trajectory.fps))
        shape = outline(scene.world, trajectory.positions[frame], trajectory.angles[frame], particle)
        _, start, velocity = module.missile_path(launch)
        if inside:
            assert tuple(normal) == (0.0, 0.0) and shape.buffer(1e-9).contains(Point(point))
            continue
        assert shape.exterior.distance(Point(point)) < 1e-6 and np.hypot(*normal) == pytest.approx(1.0)
        assert normal @ velocity < 0
        shapes.add(int(scene.world.shapes[particle]))
    assert shapes, "every missile started inside a particle"


def test_raycast_missile_starting_inside_a_particle_says_so():
    """A particle that moved onto the missile during a step: the query answers inside, normal
    (0, 0), and the scene keeps that and says the particle moved onto it."""
    module = scene_module("raycast")
    start_time, start, velocity = module.missile_path(0)
    before_time, after_time = 0.1, 0.1 + 1 / 60
    origin = start + velocity * before_time
    centre = origin + np.array([0.1, -0.2])
    world = collisim.World(positions=[centre], velocities=[[0.0, 0.0]], radii=0.5, box=module.BOX)

    def frame(time):
        return FrameState(time, 0, world.positions, world.velocities, world.angles, 0, 0, 0, 0, None, memory=memory)
    memory = {}
    assert module.missile_hits(world)(frame(before_time), frame(after_time)) == 1
    when, point, normal, particle, inside = memory["missile hits"][0]
    assert inside and particle == 0 and tuple(normal) == (0.0, 0.0) and point == pytest.approx(origin)
    assert "moved onto it" in module.missile_status(frame(after_time), 1 / 60)


def test_polygons_captions_read_the_engines_funnel_on_every_frame():
    module = scene_module("polygons")
    scene = module.scene().with_options(seconds=2.0)
    trajectory = collisim.simulate(scene)
    n, shown = scene.world.n, 0
    for state in played_scene(scene):
        circles, boxes, oriented, touching = trajectory.hierarchy[state.sample]
        assert numbers(module.funnel(n)(state)) == [n * (n - 1) // 2, circles, boxes, oriented, touching]
        assert numbers(module.shape_tests(n)(state)) == [oriented, n * (n - 1) // 2]
        shown += touching
    assert shown > 0 and circles >= boxes >= oriented >= touching


def test_collision_map_says_its_resolution_and_counts_the_engines_map_contacts():
    import cv2
    from collisim.core.kinds import MAP
    module = scene_module("collision_map")
    rows, cols = cv2.imread(str(module.LEVEL), cv2.IMREAD_GRAYSCALE).shape     # the image, read apart
    table = module.level()
    first = module.distance_field_notes(table).items
    assert numbers(first[0].text)[:2] == [cols, rows]
    assert f"cell {module.CELL:g} = radius / {module.RADIUS / module.CELL:.1f}" in first[1].text
    scene = module.scene().with_options(seconds=1.5)
    trajectory = collisim.simulate(scene.panels[0].scene)
    for state in played_scene(scene):
        assert numbers(module.map_contacts(state)) == [int(np.sum(trajectory.events.kind[
            trajectory.events.time <= state.time + 1e-12] == MAP))]
    assert numbers(module.map_contacts(state))[0] > 0


def test_raycast_sensor_caption_counts_hits_as_brute_force_finds_them():
    """Rays that hit a particle, disc or polygon, and rays that reach a wall, as brute force
    finds them with shapely (each ray's segment against every outline but the one holding the
    sensor), and the point of the first ray that hits a particle as the query gave it."""
    from shapely.geometry import LineString
    module = scene_module("raycast")
    scene = module.scene().with_options(seconds=0.5)
    world = scene.world
    assert set(world.shapes) == {collisim.core.kinds.CIRCLE, collisim.core.kinds.POLYGON}
    for state in list(played_scene(scene))[::3]:
        origins, directions, found, holder = module.sensor_rays(world, state)
        outlines = [outline(world, state.positions, state.angles, i) for i in range(world.n)]
        particles = walls = 0
        for origin, direction in zip(origins, directions):
            ahead = np.where(direction > 0, np.array(module.BOX[2:]), np.array(module.BOX[:2])) - origin
            with np.errstate(divide="ignore"):
                wall = np.where(direction != 0, ahead / direction, np.inf).min()    # the wall it leaves by
            ray = LineString([origin, origin + module.REACH * direction])
            met = [float(np.min((np.array([c for g in getattr(m, "geoms", [m]) for c in g.coords]) - origin)
                                @ direction))
                   for i, o in enumerate(outlines) if i != holder and not (m := ray.intersection(o)).is_empty]
            first = min(met, default=np.inf)
            particles += first <= min(wall, module.REACH)
            walls += wall <= module.REACH and first > wall
        shown = numbers(module.sensor_status(world)(state))[(holder >= 0):]
        assert shown[:3] == [module.RAYS, particles, walls]
        assert shown[-1] == module.RAYS * world.n and shown[-2] <= shown[-1]
        if particles:   # the point and normal of the first ray that hits a particle, as the query gave them
            k = int(np.flatnonzero(found.kinds == found.KIND_NAMES.index("body"))[0])
            assert f"ray {k + 1} at ({found.points[k, 0]:.2f}, {found.points[k, 1]:.2f})" in module.sensor_example(world)(state)


@pytest.mark.parametrize("shape", ["disc", "polygon"])
def test_raycast_sensor_inside_a_particle_looks_past_it_and_says_so(shape):
    """A particle, disc or polygon, drifting over the sensor: its rays look past it (the query
    has no surface in front of a ray that starts inside), every point and normal shown is
    another surface's, and the caption says which particle the sensor is in."""
    module = scene_module("raycast")
    scene = module.scene().with_options(seconds=0.1)
    world = scene.world
    state = next(iter(played_scene(scene)))
    state.positions = state.positions.copy()
    kind = collisim.core.kinds.POLYGON if shape == "polygon" else collisim.core.kinds.CIRCLE
    holder = int(np.flatnonzero(world.shapes == kind)[0])
    state.positions[holder] = module.SENSOR + [0.1, -0.05]
    apart = np.hypot(*(state.positions - state.positions[holder]).T) - world.radii - world.radii[holder]
    state.positions[(apart < 0) & (np.arange(world.n) != holder)] += [0.0, 3.0]   # clear room around it
    state.memory.clear()
    starts, directions, found, inside = module.sensor_rays(world, state)
    assert inside == holder
    hit = np.isfinite(found.distance)
    assert not found.inside.any() and np.allclose(np.hypot(*found.normals[hit].T), 1.0)
    assert not np.any((found.kinds == found.KIND_NAMES.index("body")) & (found.indices == holder))
    assert module.sensor_status(world)(state).startswith(f"sensor in particle {holder}, looking past it:")


def test_tunneling_remedies_slower_or_more_frames_miss_none_where_the_fast_run_misses():
    """The video's easy remedies, counted on screen from the played samples and here from the
    engine's own runs: the fast particles tunnel, slowed down or at eight times the frames a
    second they do not."""
    from collisim.render.timeline import make_players
    module = scene_module("tunneling")
    chapter_scene = module.scene().chapters[0]
    job = collisim.pipeline.plan(module.scene(), quality="l")
    players = make_players(job.chapters[0], job.size, job.fps)
    for frame in range(job.chapters[0].frames):
        for player in players:
            player.advance(frame)
    missed = []
    for player, panel in zip(players, chapter_scene.panels):
        trajectory = collisim.simulate(panel.scene)
        frames = list(states(trajectory))[:player.state.sample + 1]
        once = module.MissedOnce(module.barrier_crossings)
        missed.append(sum(once(before, after) for before, after in zip(frames, frames[1:])))
        assert player.state.counters["missed"] == missed[-1]
    assert missed[0] > 0 and missed[1:] == [0, 0]
    assert [panel.scene.fps for panel in chapter_scene.panels] == [60, 60, 60 * module.REMEDY]
