"""Bad worlds and scenes are one ValueError line in the product's words, before anything runs."""
import re
import warnings

import numpy as np
import pytest

import collisim

BAD_WORLDS = {
    "one body written flat": (dict(positions=[1.0, 2.0]), r"positions must have shape \(n, 2\).*\[\[x, y\]\]"),
    "velocities of the wrong shape": (dict(positions=[[1, 1]], velocities=[1, 2, 3]),
                                      r"velocities must have shape \(1, 2\) for 1 body, got shape \(3,\)"),
    "restitution None": (dict(positions=[[1, 1]], restitution=None), "restitution must be a number"),
    "restitution text": (dict(positions=[[1, 1]], restitution="1"), "restitution must be a number"),
    "restitution above 1": (dict(positions=[[1, 1]], restitution=1.5), r"restitution must be in \[0, 1\]"),
    "radius too small for an area": (dict(positions=[[1, 1]], radii=1e-300), "radius 1e-300 of body 0 is too small"),
    "box upside down": (dict(positions=[[1, 1]], box=(0, 0, -1, 1)), r"box must have xmax > xmin.*\[0.0, 0.0, -1.0"),
    "NaN velocity": (dict(positions=[[1, 1]], velocities=[[np.nan, 0]]), "velocities contains NaN or inf"),
    "segments of three numbers": (dict(positions=[[1, 1]], segments=[[0, 0, 1]]), r"segments must have shape \(m, 4\)"),
    "negative friction": (dict(positions=[[1, 1]], friction=-1), "friction must be >= 0, got -1"),
    "radii None": (dict(positions=[[1, 1]], radii=None), "radii must be numbers, got None"),   # was 'contains NaN'
    "masses of None": (dict(positions=[[1, 1], [3, 3]], masses=[1.0, None]), "masses contains NaN or inf"),
    "particle through a wall": (dict(positions=[[5, 0.2]], radii=0.5),
                                r"particle 0 \(radius 0.5\) at \(5, 0.2\) reaches 0.3 beyond the box's bottom wall"),
    "ball as tall as the box, moving up": (dict(positions=[[50, 5]], velocities=[[3, 1]], radii=5, box=(0, 0, 100, 10)),
                                           r"particle 0 \(radius 5\) fills the box's height and cannot move across "
                                           r"it; give it no vertical velocity \(it has 1\)"),
    "box as wide as the box, moving sideways": (dict(positions=[[1, 5]], velocities=[[-2, 0]], box=(0, 0, 2, 10),
                                                     polygons=[[[-1, -0.5], [1, -0.5], [1, 0.5], [-1, 0.5]]]),
                                                r"polygon 0 fills the box's width .* horizontal velocity \(it has -2\)"),
    "tilted box through the floor": (dict(positions=[[5, 0.25]], polygons=[[[-0.5, -0.25], [0.5, -0.25], [0.5, 0.25],
                                                                              [-0.5, 0.25]]], angles=[0.01]),
                                     r"polygon 0 at \(5, 0.25\) reaches 0.00499 beyond the box's bottom wall"),
}


@pytest.mark.parametrize("case", BAD_WORLDS)
def test_bad_world_is_one_clear_line(case):
    kwargs, message = BAD_WORLDS[case]
    with pytest.raises(ValueError, match=message) as error:
        collisim.World(**kwargs)
    text = str(error.value)
    assert "\n" not in text and "np.float64" not in text and "array(" not in text


@pytest.mark.parametrize("method", ["ccd", "discrete"])
def test_a_ball_as_tall_as_a_tube_rolls_along_it(method):
    """Filling the box's height, with no vertical velocity, is allowed: both methods carry the
    ball along the tube at its speed, as they would a ball with room to spare."""
    world = collisim.World(positions=[[50, 5]], velocities=[[3, 0]], radii=5, box=(0, 0, 100, 10))
    run = collisim.simulate(collisim.Scene(world=world, fps=60, seconds=1, method=method))
    assert not run.approximate.any()
    assert np.allclose(run.positions[-1], [[53, 5]], rtol=0, atol=1e-12)
    assert np.allclose(run.velocities[-1], [[3, 0]], rtol=0, atol=1e-12)


# What only the engine can tell (its narrow phase, its registries) is refused where it starts:
# by simulate, and by render before any file is written.
BAD_STARTS = {
    "overlapping bodies": (dict(world=dict(positions=[[1, 1], [1.5, 1]], radii=0.5)), "bodies 0 and 1 overlap by 0.5"),
    "coincident bodies": (dict(world=dict(positions=[[3, 3], [6, 6], [3, 3]], radii=0.5)),
                          "bodies 0 and 2 overlap by 1"),
    "body on a segment": (dict(world=dict(positions=[[5, 5]], radii=0.5, segments=[[0, 5, 10, 5]])),
                          "body 0 overlaps segment 0 by 0.5"),
    "overlapping polygons": (dict(world=dict(positions=[[2, 2], [2.5, 2]], polygons=[[[-0.5, -0.5], [0.5, -0.5],
                                                                                    [0.5, 0.5], [-0.5, 0.5]]] * 2)),
                             "bodies 0 and 1 overlap by 0.5"),
    "unknown method": (dict(method="verlet"), "unknown method 'verlet'; choose one of: discrete, ccd"),
    "unknown broad phase": (dict(broadphase="octree"), "unknown broad phase 'octree'; choose one of: auto, brute"),
    "friction under ccd": (dict(world=dict(positions=[[5, 5]], friction=0.5), method="ccd"),
                           r"ccd covers frictionless contacts only .* friction=0.5: use method discrete"),
}


def _start_scene(case):
    options, message = BAD_STARTS[case]
    world = collisim.World(**options.get("world", dict(positions=[[1, 1]])))   # the model takes it as given
    scene_options = {key: value for key, value in options.items() if key != "world"}
    return collisim.Scene(world=world, fps=30, seconds=0.5, **scene_options), message


@pytest.mark.parametrize("case", BAD_STARTS)
def test_what_the_engine_cannot_start_is_one_clear_line(case):
    scene, message = _start_scene(case)
    with pytest.raises(ValueError, match=message) as error:
        collisim.simulate(scene)
    assert "\n" not in str(error.value)
    with pytest.raises(ValueError, match=message):
        next(collisim.stream(scene))


@pytest.mark.parametrize("case", ["overlapping bodies", "unknown method"])
def test_what_the_engine_cannot_start_is_refused_before_a_render_writes(case, tmp_path):
    scene, message = _start_scene(case)
    panels = collisim.Scene(panels=[collisim.Panel(scene.replace(world=collisim.World([[1, 1]])), "fine"),
                                    collisim.Panel(scene, "bad")], fps=30, seconds=0.5)
    for source in (scene, panels):
        with pytest.raises(ValueError, match=message):
            collisim.render(source, tmp_path / "out.mp4")
    assert list(tmp_path.iterdir()) == []


def test_touching_bodies_and_segments_are_allowed():
    r = 0.5
    angle = 0.7   # touching along a diagonal, as arithmetic places them (rounding included)
    second = [2.0 + 2 * r * np.cos(angle), 2.0 + 2 * r * np.sin(angle)]
    world = collisim.World([[2.0, 2.0], second, [5.0, 5.5]], radii=r, segments=[[0, 5, 10, 5]])
    run = collisim.simulate(collisim.Scene(world=world, fps=30, seconds=0.1))
    assert run.frames == 3


BAD_SCENES = {
    "fps as text": (dict(fps="60"), "fps must be a number, got '60'"),
    "fps zero": (dict(fps=0), "fps must be a finite number > 0"),
    "seconds NaN": (dict(seconds=float("nan")), "seconds must be a finite number > 0"),
    "substeps fractional": (dict(substeps=2.5), "substeps must be a whole number >= 1, got 2.5"),
    "negative rest speed": (dict(rest_speed=-1), "rest_speed must be >= 0, got -1"),
    "negative tc": (dict(tc=-0.5), "tc must be >= 0, got -0.5"),
}


@pytest.mark.parametrize("case", BAD_SCENES)
def test_bad_scene_is_one_clear_line(case):
    kwargs, message = BAD_SCENES[case]
    with pytest.raises(ValueError, match=message):
        collisim.Scene(world=collisim.World([[1, 1]]), **kwargs)


def test_a_duration_that_is_not_a_whole_number_of_frames_is_rounded_and_said():
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        scene = collisim.Scene(world=collisim.World([[1, 1]]), fps=60, seconds=1.01)
        exact = collisim.Scene(world=collisim.World([[1, 1]]), fps=60, seconds=2.0)
    assert scene.frames == 61 and exact.frames == 120
    assert [str(w.message) for w in caught] == ["1.01 s at 60 fps is 60.6 frames; using 61 frames (1.01667 s)"]


def test_a_frame_rate_and_a_length_given_together_are_checked_together():
    """--physics-fps 0.05 --seconds 40 is two frames: valid, though 0.05 fps over the scene's own
    10 s is under one frame; and an error names the length asked for, not the scene's."""
    scene = collisim.load_scene("particles_250")
    assert scene.seconds * 0.05 < 1
    assert scene.with_options(fps=0.05, seconds=40).frames == 2
    with pytest.raises(ValueError, match=r"^seconds=0\.1 at fps=1e-09 is shorter than one frame$"):
        scene.with_options(fps=1e-9, seconds=0.1)


@pytest.mark.parametrize("gravity, words", [(-9.81, "a vector of two numbers, such as (0, -9.81), got -9.81"),
                                            ((0, 1, 2), "a vector of two numbers"),
                                            ([[0, -9.81]], "a vector of two numbers"),
                                            ((0, np.nan), "NaN or inf"), (("a", 1), "must be numbers")])
def test_gravity_is_one_vector(gravity, words):
    """A scalar would have been copied into both components: a diagonal pull nobody asked for."""
    with pytest.raises(ValueError, match=re.escape(words)):
        collisim.World([[1, 1], [3, 3]], gravity=gravity)
    assert collisim.World([[1, 1], [3, 3]], gravity=(0, -9.81)).accelerations.tolist() == [[0, -9.81]] * 2


def test_a_state_that_overflows_is_refused_at_its_first_frame_whatever_the_block_size():
    """A gravity whose speeds square to more than double precision holds: the discrete step's
    arithmetic gave inf, then NaN, within the first frame, and the frames went on as NaN."""
    world = collisim.World(positions=[[5, 5], [2, 2]], velocities=[[1, 0], [0, 0]], radii=0.5, gravity=(0, 1e300))
    scene = collisim.Scene(world=world, fps=30, seconds=1.0, method="discrete")
    for block in (1, 2, 3, 64):   # block 1: the first block is the t = 0 sample alone
        with pytest.raises(ValueError, match=r"the discrete method overflowed at frame 1 \(t = 0.03333 s\)") as error:
            for _ in collisim.stream(scene, block=block):
                pass
        assert "\n" not in str(error.value)
    with pytest.raises(ValueError, match="overflowed at frame 1"):
        collisim.simulate(scene)


@pytest.mark.parametrize("field", ["positions", "velocities", "angles", "angular_velocities"])
def test_the_frame_named_is_the_first_not_finite_counted_from_the_block_start(field):
    import importlib
    simulating = importlib.import_module("collisim.engine.simulate")   # the module, not the function
    from collisim.engine.frames import new_frames

    scene = collisim.Scene(world=collisim.World(positions=[[5, 5], [2, 2]], radii=0.5), fps=30, seconds=1.0)
    frames = new_frames(6, 2)
    for name in ("positions", "velocities", "angles", "angular_velocities"):
        getattr(frames, name)[:] = 1.0
    simulating.require_finite(frames, 10, scene)     # all finite: nothing said
    getattr(frames, field)[3:, 1] = np.inf           # from the block's fourth frame on
    getattr(frames, field)[5, 0] = np.nan
    with pytest.raises(ValueError, match=r"overflowed at frame 13 \(t = 0.4333 s\)"):
        simulating.require_finite(frames, 10, scene)


def test_a_panel_or_chapter_of_too_many_steps_is_refused_before_anything_runs():
    from collisim.pipeline import plan

    world = collisim.World(positions=[[5, 5]], radii=0.5)
    fine = collisim.Scene(world=world, fps=60, seconds=2.0, substeps=4)
    endless = collisim.Scene(world=world, fps=1e9, seconds=2.0, name="endless")
    plan(collisim.Scene(panels=[collisim.Panel(fine), collisim.Panel(fine)], fps=60, seconds=2.0))
    for scene in (collisim.Scene(panels=[collisim.Panel(fine), collisim.Panel(endless)], fps=60, seconds=2.0),
                  collisim.Scene(chapters=[fine, endless], fps=60, seconds=4.0)):
        with pytest.raises(ValueError, match=r"scene 'endless' would take 2000000000 simulation steps"):
            plan(scene)
        plan(scene, limits=False)   # planned, not run


def test_a_count_of_steps_too_large_to_read_is_said_in_three_digits():
    from collisim.pipeline import plan

    world = collisim.World(positions=[[5, 5]], radii=0.5)
    with pytest.raises(ValueError, match=r"^scene 'huge' would take 2e\+299 simulation steps \(2e\+299 frames at 1e\+300 "
                                         r"fps\), more than 10000000; use --no-limits to run it anyway$"):
        plan(collisim.Scene(world=world, fps=1e300, seconds=0.2, name="huge"))


BAD_RENDER_SETTINGS = {
    "trails of a fraction": (dict(trails=2.5), r"trails must be a whole number of frames >= 0, got 2.5"),
    "negative trails": (dict(trails=-1), r"trails must be a whole number of frames >= 0, got -1"),
    "arrows reaching NaN seconds": (dict(arrow_seconds=float("nan")), "arrow_seconds must be a finite number > 0"),
    "a layout of no rows": (dict(layout=(0, 2)), r"layout must be two whole numbers >= 1, got \(0, 2\)"),
    "a size of no pixels": (dict(size=(0, 0)), r"size must be two whole numbers >= 1"),
    "an overlay that is a number": (dict(overlay=5), r"overlay must be a function overlay\(canvas, view, state\)"),
    "a counter that is a number": (dict(counters={"missed": 3}), "counters must map names to functions"),
    "an explainer that is text": (dict(explainer="captions"), "explainer must be an Explainer"),
}


@pytest.mark.parametrize("case", BAD_RENDER_SETTINGS)
def test_bad_render_settings_are_one_line_before_anything_runs(case):
    """Each failed mid-render before: TypeError, ZeroDivisionError, or OpenCV's overload error."""
    kwargs, message = BAD_RENDER_SETTINGS[case]
    with pytest.raises(ValueError, match=message) as error:
        collisim.RenderSettings(**kwargs)
    assert "\n" not in str(error.value)


def test_angles_and_angular_velocities_left_as_none_are_zero():
    """None, like velocities=None, means the default (it read 'angles contains NaN or inf')."""
    world = collisim.World([[5.0, 5.0]], angles=None, angular_velocities=None)
    assert world.angles.tolist() == [0.0] and world.angular_velocities.tolist() == [0.0]


@pytest.mark.parametrize("n", [200, 5000])   # checked in numpy, and through the contacts query
def test_the_first_overlapping_pair_is_named_as_brute_force_finds_it(n):
    from scipy.spatial import cKDTree
    rng = np.random.default_rng(n)
    side = 6.0 * np.sqrt(n)   # sparse: a few pairs in a hundred bodies overlap
    positions, radii = rng.uniform(1.0, side - 1.0, (n, 2)), rng.uniform(0.3, 0.6, n)
    pairs = np.array(sorted(cKDTree(positions).query_pairs(1.2)))
    depths = radii[pairs].sum(axis=1) - np.hypot(*(positions[pairs[:, 1]] - positions[pairs[:, 0]]).T)
    deep = np.flatnonzero(depths > 1e-9 * radii[pairs].sum(axis=1))
    assert 1 < deep.size < n // 10
    i, j = pairs[deep[0]]
    world = collisim.World(positions, radii=radii, box=(0.0, 0.0, side, side))
    with pytest.raises(ValueError, match=rf"^bodies {i} and {j} overlap by {depths[deep[0]]:.3g} at the start"):
        collisim.simulate(collisim.Scene(world=world, fps=30, seconds=0.1))
