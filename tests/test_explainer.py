"""The explainer layer: captions stay in their strips and notes in their panel at every size,
items appear and fade on time, and an item can wait for an event the engine found."""
import math

import numpy as np
import pytest

import collisim
from collisim.render import explain
from collisim.render.explain import Arrow, Caption, Explainer, Figure, Mark, Note
from collisim.render.pace import Freeze, Slow
from collisim.render.text import fit_width, text_image
from collisim.render.timeline import Timeline


def scenes_within(scene):
    """The scene and every scene in its panels and chapters."""
    inner = [p.scene for p in scene.panels] + list(scene.chapters)
    return [scene] + [s for part in inner for s in scenes_within(part)]


def key_frames(scene, quality, count=6):
    """`count` video frames spread over the render at that quality, and three in every chapter
    (a third, two thirds and the end of it), so each chapter's build is measured."""
    job = collisim.pipeline.plan(scene, quality=quality)
    starts = np.cumsum([0] + [c.frames for c in job.chapters])
    inside = [int(start + share * (c.frames - 1)) for start, c in zip(starts, job.chapters) for share in (0.33, 0.66, 1.0)]
    return np.unique(np.concatenate([np.linspace(0, job.frames - 1, count).astype(int), inside]))


@pytest.mark.parametrize("name", ["single_bounce", "two_bodies", "teacher_drop", "tunneling", "broadphase_six", "frame_rate",
                                  "bounding_volumes"])
@pytest.mark.parametrize("quality", ["l", "h"])
def test_explained_scenes_keep_text_in_its_strips_and_panel(name, quality, tmp_path):
    scene = collisim.load_scene(name)
    explainers = [s.render.explainer for s in scenes_within(scene) if s.render.explainer is not None]
    seen = set()
    job = collisim.pipeline.plan(scene, quality=quality)
    timeline = Timeline(job.chapters, job.size, job.fps)
    canvas = np.empty((job.size[1], job.size[0], 3), np.uint8)
    for frame in key_frames(scene, quality, 10):   # one pass through the video, drawing key frames
        for explainer in explainers:
            explainer.drawn = []
        timeline.draw(canvas, int(frame))
        for explainer in explainers:
            for kind, rect, bound in explainer.drawn:
                assert explain.inside(rect, bound), (quality, frame, kind, rect, bound)
                seen.add(kind)
    assert "caption" in seen
    if name in ("broadphase_six", "bounding_volumes"):
        assert "figure" in seen     # the structures, the sweep's lanes and the grid's chart stay in their regions


def ink(image):
    """Rows and columns the text's coverage reaches."""
    return np.count_nonzero(image.max(axis=1) > 0.05), np.count_nonzero(image.max(axis=0) > 0.05)


def test_text_grows_with_the_frame():
    small, large = text_image("p = v t", 17.0), text_image("p = v t", 17.0 * 2.25)
    (small_rows, small_cols), (large_rows, large_cols) = ink(small), ink(large)
    assert 2.0 < large_rows / small_rows < 2.5 and 2.0 < large_cols / small_cols < 2.5
    assert 0.0 < small.max() <= 1.0


def test_text_is_whole_within_its_image():
    """No glyph is cut at the image's sides (a T's arm standing out of its advance, a last
    letter): the image holds all the ink of the same text typeset with room on either side."""
    from matplotlib.font_manager import FontProperties
    from matplotlib.mathtext import MathTextParser
    for text in ("T", "VAT", "j", "reflected", r"the update $p \leftarrow p + v\,\Delta t$"):
        for pixels in (17.0, 38.5, 76.5):
            roomy = MathTextParser("agg").parse(r"$\,$" + text + r"$\,$", dpi=72, prop=FontProperties(size=pixels))
            all_of_it = np.asarray(roomy.image, np.float64).sum() / 255.0
            assert text_image(text, pixels).sum() == pytest.approx(all_of_it, rel=1e-6), (text, pixels)


def test_items_fade_in_and_out_on_the_timeline():
    item = Caption("x", 1.0, 2.0)
    layer = Explainer([item], fade=0.5)

    class State:
        events = None
    state = State()
    for time, expected in ((0.4, 0.0), (0.75, 0.5), (1.0, 1.0), (1.5, 1.0), (2.25, 0.5), (2.6, 0.0)):
        state.time = time
        assert layer.opacity(item, state) == pytest.approx(expected)


def test_an_item_can_wait_for_an_event_and_keeps_its_moment():
    answers = iter([None, None, 3.0, None])
    item = Note("bounce", (0.0, 0.0), start=lambda state: next(answers))
    layer = Explainer([item], fade=0.0)

    class State:
        time = 5.0

        def __init__(self, memory):
            self.memory = memory   # the panel's, kept for its play (FrameState.memory)
    play = {}
    assert layer.opacity(item, State(play)) == 0.0      # not yet
    assert layer.opacity(item, State(play)) == 0.0
    assert layer.opacity(item, State(play)) == 1.0      # the event happened at 3.0
    assert layer.opacity(item, State(play)) == 1.0      # and stays known for the rest of the play
    answers = iter([None])
    assert layer.opacity(item, State({})) == 0.0        # another play asks again


def test_a_long_caption_shrinks_to_its_strip():
    image = text_image("a rather long caption " * 6, 17.0)
    fitted = fit_width(image, 200)
    assert fitted.shape[1] <= 200 and fitted.shape[0] < image.shape[0]
    assert math.isclose(fitted.shape[0] / image.shape[0], 200 / image.shape[1], rel_tol=0.1)


def test_pace_maps_video_time_to_simulation_time_and_back():
    from collisim.render.pace import Freeze, Pace, Slow
    pace = Pace(Slow(1.0, 2.0, 0.25), Freeze(3.0, 2.0))
    assert pace.extra == pytest.approx(3.0 + 2.0)
    expected = {0.5: 0.5, 1.0: 1.0, 3.0: 1.5, 5.0: 2.0, 6.0: 3.0, 7.0: 3.0, 8.0: 3.0, 9.0: 4.0}
    for video, sim in expected.items():
        assert pace.simulation_time(video) == pytest.approx(sim)
    assert pace.video_time(3.0) == pytest.approx(6.0)     # a freeze starts where its moment is first shown
    with pytest.raises(ValueError, match="overlaps"):
        Pace(Slow(1.0, 2.0, 0.5), Freeze(1.5, 1.0))


def test_a_paced_scene_plays_longer_and_holds_its_frozen_sample():
    scene = collisim.load_scene("two_bodies")
    job = collisim.pipeline.plan(scene, quality="l")
    assert job.frames == round((scene.seconds + scene.render.pace.extra) * 15)


@pytest.mark.parametrize("make, words", [
    (lambda: Freeze(float("nan"), 1.0), "Freeze needs a finite time and finite seconds > 0"),
    (lambda: Freeze(1.0, float("inf")), "Freeze needs a finite time and finite seconds > 0"),
    (lambda: Slow(0.0, float("inf"), 0.5), "Slow needs finite times, end > start"),
    (lambda: Slow(1.0, 0.5, 0.5), "Slow needs finite times, end > start"),
])
def test_a_pace_of_impossible_times_is_one_clear_line(make, words):
    with pytest.raises(ValueError, match=words):
        make()


@pytest.mark.parametrize("make, words", [
    (lambda: Caption("x", float("nan"), 1.0), "Caption start must be seconds, None or a function of the state"),
    (lambda: Caption("x", 0.0, 1.0, "middle"), "Caption strip must be one of 'top', 'bottom', got 'middle'"),
    (lambda: Caption("x", 0.0, 1.0, "top", -1), "Caption line must be a whole number >= 0"),
    (lambda: Figure(lambda *a: None, 0.0, 1.0, "left"), "Figure place must be one of 'side', 'top', 'bottom', 'box'"),
    (lambda: Mark((-1,), 0.0, 1.0), r"Mark bodies must be body numbers >= 0, got \(-1,\)"),
    (lambda: Explainer([Caption("x")], lines=-1), "Explainer lines must be a whole number >= 0"),
    (lambda: Explainer(["a caption"]), "an Explainer holds Caption, Arrow, Mark, Note and Figure items"),
    (lambda: Explainer([Caption("x")], clock="wall"), "Explainer clock must be one of 'simulation', 'video'"),
])
def test_an_explainer_item_made_wrong_is_one_line_when_it_is_made(make, words):
    """Each failed mid-render before (KeyError, IndexError, TypeError) or drew nothing."""
    with pytest.raises(ValueError, match=words):
        make()


def test_what_a_render_can_only_know_is_one_line_before_the_video_is_written(tmp_path):
    world = collisim.World([[5.0, 5.0], [2.0, 2.0]], [[1.0, 0.0], [0.0, 1.0]], radii=0.5)

    def scene(item):
        return collisim.Scene(world=world, fps=30, seconds=0.5,
                              render=collisim.RenderSettings(explainer=Explainer([item])))
    with pytest.raises(ValueError, match=r"Mark names body 7, and the world has 2 bodies \(0 to 1\)"):
        collisim.render(scene(Mark((7,))), tmp_path / "mark.mp4", (320, 180), progress=False)
    with pytest.raises(ValueError, match=r"text '\$x\^2' is not valid mathtext \(an odd number of \$ signs"):
        collisim.render(scene(Caption(r"$x^2")), tmp_path / "math.mp4", (320, 180), progress=False)
    assert list(tmp_path.iterdir()) == []
    # an arrow whose end is not known yet, and a note whose text is not, are left out, not an error
    unknown = collisim.render(scene(Arrow((1.0, 1.0), lambda s: np.array([np.nan, 0.0]))), tmp_path / "a.mp4",
                              (320, 180), progress=False)
    blank = collisim.render(scene(Note(lambda s: None, (1.0, 1.0))), tmp_path / "n.mp4", (320, 180), progress=False)
    assert unknown.exists() and blank.exists()
