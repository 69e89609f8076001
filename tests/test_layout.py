"""The layout of a frame's labels (render/layout.py), on every shipped scene at -ql and -qh: no
note, mark, tag or arrow label crosses a line of the box, a body or another label; none leaves
its region; every text, the HUD's too, is at least the minimum size. The geometry is checked
here on its own terms (points along the lines, the bodies' discs and outlines), not with the
placer's functions, and once on a frame as the command line writes it."""
import cv2
import numpy as np
import pytest

import collisim
import collisim.cli
from collisim import palette
from collisim.core.kinds import CIRCLE
from collisim.model.scenefile import available_scenes
from collisim.render import raster
from collisim.render.layout import Layout, min_text_pixels
from collisim.render.timeline import Timeline

IN_THE_BOX = ("note", "mark", "arrow", "tag", "status")   # labels placed among the bodies
SHARES = (0.4, 0.7, 0.97)   # the moments of each chapter looked at: its explanations build up


def sampled_frames(job) -> list:
    starts = np.cumsum([0] + [c.frames for c in job.chapters])
    return sorted({int(start + share * (c.frames - 1)) for start, c in zip(starts, job.chapters) for share in SHARES})


def inside(rect, bound) -> bool:
    x, y, w, h = rect
    bx, by, bw, bh = bound
    return bx <= x and by <= y and x + w <= bx + bw and y + h <= by + bh


def points_in(rect, points) -> np.ndarray:
    x, y, w, h = rect
    return (points[:, 0] > x) & (points[:, 0] < x + w) & (points[:, 1] > y) & (points[:, 1] < y + h)


def along(starts, ends, step=1.0) -> np.ndarray:
    """Points every `step` pixels along each segment."""
    out = []
    for a, b in zip(starts, ends):
        count = int(np.hypot(*(b - a)) / step) + 2
        out.append(a + np.linspace(0.0, 1.0, count)[:, None] * (b - a))
    return np.concatenate(out) if out else np.zeros((0, 2))


def box_lines(player) -> np.ndarray:
    """Points along the box's edges and the world's segments, in pixels."""
    world, view = player.world, player.view
    xmin, ymin, xmax, ymax = world.box
    corners = view.to_pixels([[xmin, ymin], [xmax, ymin], [xmax, ymax], [xmin, ymax]])
    points = [along(corners, np.roll(corners, -1, axis=0))]
    if len(world.segments):
        segments = np.asarray(world.segments, float).reshape(-1, 4)
        points.append(along(view.to_pixels(segments[:, :2]), view.to_pixels(segments[:, 2:])))
    return np.concatenate(points)


def body_meets(player, rect) -> list:
    """The bodies of the player's sample whose disc or outline reaches into rect."""
    world, view, state = player.world, player.view, player.state
    x, y, w, h = rect
    centres, radii = view.to_pixels(state.positions), view.length(world.radii)
    nearest = np.clip(centres, [x, y], [x + w, y + h])
    circles = world.shapes == CIRCLE
    met = np.flatnonzero(circles & (np.hypot(*(nearest - centres).T) < radii - 0.5)).tolist()
    if not circles.all():
        outlines, bodies = raster.polygon_outlines(world, state.positions, state.angles)
        for outline, body in zip(outlines, bodies):
            pixels = view.to_pixels(outline)
            edge = along(pixels, np.roll(pixels, -1, axis=0))
            if points_in(rect, edge).any() or points_in(rect, pixels.mean(axis=0)[None]).any():
                met.append(int(body))
    return met


def overlap(a, b) -> bool:
    return a[0] < b[0] + b[2] and b[0] < a[0] + a[2] and a[1] < b[1] + b[3] and b[1] < a[1] + a[3]


def check_frame(timeline, frame, least) -> set:
    """Every label of the frame against the rules; returns the kinds seen."""
    kinds, by_player = set(), {}
    for player, label in timeline.placed():
        where = (frame, label.kind, label.text, label.rect)
        kinds.add(label.kind)
        assert inside(label.rect, label.bound), where
        assert label.pixels >= least - 1e-9, (where, label.pixels, least)
        if label.kind in IN_THE_BOX:
            assert label.fits, where
            assert not points_in(label.rect, box_lines(player)).any(), where
            assert not body_meets(player, label.rect), where
        by_player.setdefault(id(player), []).append(label)
    for labels in by_player.values():
        for k, a in enumerate(labels):
            for b in labels[k + 1:]:
                assert not overlap(a.rect, b.rect), (frame, a, b)
    return kinds


def walk(name, quality):
    scene = collisim.load_scene(name)
    job = collisim.pipeline.plan(scene, quality=quality)
    timeline = Timeline(job.chapters, job.size, job.fps)
    canvas = np.empty((job.size[1], job.size[0], 3), np.uint8)
    least, kinds = min_text_pixels(job.size[1]), set()
    for frame in sampled_frames(job):
        timeline.draw(canvas, frame)
        kinds |= check_frame(timeline, frame, least)
    timeline.close()
    return kinds


SCENES = sorted(available_scenes())


@pytest.mark.parametrize("name", SCENES)
def test_labels_keep_clear_of_lines_bodies_and_each_other_at_480p(name):
    kinds = walk(name, "l")
    assert kinds & {"hud", "caption"}   # every scene writes some text


@pytest.mark.slow
@pytest.mark.parametrize("name", SCENES)
def test_labels_keep_clear_of_lines_bodies_and_each_other_at_1080p(name):
    walk(name, "h")


def test_the_labels_of_the_found_cases_are_placed():
    """The scenes the issue found labels over lines and bodies in do place their labels."""
    assert {"note"} <= walk("tunneling", "l")
    assert {"tag"} <= walk("bounding_volumes", "l")


def test_a_crowded_place_moves_a_label_to_the_nearest_free_one_and_says_when_none_is():
    layout = Layout((0, 0, 200, 100), pad=1.0)
    layout.add_discs([[50.0, 50.0]], 10.0)
    first = layout.place((40, 10), (50, 50), "note", "a", 12.0, gap=10.0)
    assert first.fits and first.rect[0] >= 61 and not first.leader            # to its right, beside the disc
    second = layout.place((40, 10), (50, 50), "note", "b", 12.0, gap=10.0)
    assert second.fits and not overlap(first.rect, second.rect)               # the next free place
    full = Layout((0, 0, 30, 30))
    assert not full.place((40, 10), (15, 15), "note", "c", 12.0).fits          # wider than the frame


def test_a_label_on_a_frame_as_written_sits_on_no_body_and_no_line(tmp_path):
    """single_bounce's "extreme point" note (it crossed the floor): in the PNG the command line
    writes, the note's rectangle holds its text's ink, and none of the ball's or the box's
    colour; its letters are at least the minimum size tall."""
    scene = collisim.load_scene("single_bounce")
    job = collisim.pipeline.plan(scene, quality="l")
    frame = int(1.2 * job.fps)
    timeline = Timeline(job.chapters, job.size, job.fps)
    canvas = np.empty((job.size[1], job.size[0], 3), np.uint8)
    for k in range(frame + 1):
        timeline.draw(canvas, k)
    notes = [label for _, label in timeline.placed() if label.kind == "note"]
    assert len(notes) == 1
    out = tmp_path / "still.png"
    assert collisim.cli.main(["render", "single_bounce", "-ql", "--png", str(frame), "--out", str(out),
                              "--no-progress"]) == 0
    image = cv2.imread(str(out))[:, :, ::-1].astype(int)
    x, y, w, h = notes[0].rect
    region = image[y:y + h, x:x + w]
    text = np.abs(region - np.array(palette.TEXT)).sum(axis=2) < 60
    rows = np.flatnonzero(text.any(axis=1))
    assert text.sum() > 30 and rows[-1] - rows[0] + 1 >= 0.73 * min_text_pixels(job.size[1])
    assert not (np.abs(region - np.array(scene.world.colors[0], int)).sum(axis=2) < 30).any()   # no ball
    # no wall: a line of the box would run the rectangle's whole width or height (the text's ink is
    # the box's colour nearly, and never does)
    line = np.abs(region - np.array(palette.BOX, int)).sum(axis=2) < 40
    assert not line.all(axis=1).any() and not line.all(axis=0).any()
