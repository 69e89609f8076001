"""The compiled disc and ring rasterizer (render/splat.py) against exact covered areas.

Every tolerance below is one of the bounds stated in coverage.py's docstring, measured over radii
0.5 to 200 px at random sub-pixel positions, with a margin of about 20 %."""
import hashlib
import subprocess
import sys

import cv2
import numpy as np
import pytest

from collisim.render import bands, raster, splat
from collisim.render.splat import disc_coverage, draw_discs, ring_coverage


# --- exact areas, for reference -------------------------------------------------------------------

def _integral(t, r):
    """The integral of sqrt(r^2 - u^2) over u in [0, t], |t| <= r."""
    return 0.5 * (t * np.sqrt(np.maximum(r * r - t * t, 0.0)) + r * r * np.arcsin(np.clip(t / r, -1.0, 1.0)))


def _below_left(x, y, r):
    """Area of the disc of radius r centred at 0 where X <= x and Y <= y."""
    x, y = np.clip(x, -r, r), np.clip(y, -r, r)
    s = np.sqrt(np.maximum(r * r - y * y, 0.0))      # the chord at height y spans [-s, s]
    mid = np.clip(x, -s, s)
    area = y * (mid + s) + _integral(mid, r) - _integral(-s, r)   # over the chord: from -h(t) to y
    beyond = 2 * (_integral(np.minimum(x, -s), r) - _integral(-r, r)) + 2 * (_integral(np.maximum(x, s), r)
                                                                           - _integral(s, r))
    return area + np.where(y >= 0, beyond, 0.0)      # outside the chord: the whole height if y >= 0


def exact_coverage(shape, centre, r):
    """The exact fraction of each pixel's square covered by the disc."""
    ys, xs = np.mgrid[0:shape[0], 0:shape[1]].astype(float)
    x0, x1 = xs - 0.5 - centre[0], xs + 0.5 - centre[0]
    y0, y1 = ys - 0.5 - centre[1], ys + 0.5 - centre[1]
    return _below_left(x1, y1, r) - _below_left(x0, y1, r) - _below_left(x1, y0, r) + _below_left(x0, y0, r)


def test_the_exact_reference_is_exact():
    assert exact_coverage((9, 9), (4.0, 4.0), 0.3)[4, 4] == pytest.approx(np.pi * 0.09)
    assert exact_coverage((40, 40), (19.3, 20.8), 11.0).sum() == pytest.approx(np.pi * 121, rel=1e-12)
    quarters = exact_coverage((8, 8), (3.5, 3.5), 2.0)      # centred on a pixel corner
    for part in (quarters[:4, :4], quarters[:4, 4:], quarters[4:, :4], quarters[4:, 4:]):
        assert part.sum() == pytest.approx(np.pi, rel=1e-12)


# --- the bounds -----------------------------------------------------------------------------------

def positions(r, count, seed):
    """A canvas shape that holds the disc, and `count` random centres in its middle pixel."""
    side = int(2 * r) + 8
    rng = np.random.default_rng(seed)
    return (side, side), side / 2 + rng.uniform(0, 1, (count, 2))


def centroid(cov):
    ys, xs = np.mgrid[0:cov.shape[0], 0:cov.shape[1]]
    return np.array([(cov * xs).sum(), (cov * ys).sum()]) / cov.sum()


def area_tolerance(r):
    # below SMALL the fractions are normalized to sum to pi r^2: only rounding is left. Above,
    # the tangent line's correction alone: measured at most 0.077 px^2 (at r = 4.3), and 0.1 px^2
    # is a thousandth of a pixel per boundary pixel of a 4 px disc.
    return 1e-9 * max(r * r, 1.0) if r < splat.SMALL else 0.1


def pixel_bound(r):
    return 0.072 / r if r >= 1 else 0.09        # measured: 0.058 / r, and 0.075 below r = 1


def centroid_bound(r):
    if r < splat.TINY:
        return 1e-9
    return 0.072 / r if r >= 1 else 0.1         # measured: 0.056 / r, and 0.08 below r = 1


RADII = [0.05, 0.3, 0.45, 0.5, 0.53, 0.6, 0.8, 1.0, 1.5, 2.5, 3.99, 4.0, 6.5, 12.0, 30.0, 75.0, 200.0]


@pytest.mark.parametrize("r", RADII)
def test_a_disc_covers_pi_r_squared(r):
    shape, centres = positions(r, 12 if r < 50 else 3, seed=int(r * 100))
    for centre in centres:
        assert abs(disc_coverage(shape, centre, r).sum() - np.pi * r * r) <= area_tolerance(r)


@pytest.mark.parametrize("r", [0.5, 0.53, 0.6, 0.7, 0.8, 0.95, 1.0, 1.3, 1.7, 2.5, 3.6, 4.3, 7.5, 12.0, 40.0, 200.0])
def test_each_pixel_is_within_the_stated_bound_of_its_exact_covered_fraction(r):
    shape, centres = positions(r, 40 if r < 20 else 4, seed=int(r * 100) + 1)
    for centre in centres:
        error = np.abs(disc_coverage(shape, centre, r) - exact_coverage(shape, centre, r)).max()
        assert error <= pixel_bound(r), (centre, error)


@pytest.mark.parametrize("r", RADII)
def test_the_centroid_of_coverage_is_the_centre(r):
    shape, centres = positions(r, 30 if r < 20 else 3, seed=int(r * 100) + 2)
    for centre in centres:
        error = np.abs(centroid(disc_coverage(shape, centre, r)) - centre).max()
        assert error <= centroid_bound(r), (centre, error)


@pytest.mark.parametrize("r", [0.3, 0.5, 0.55, 0.8, 3.0, 9.0])
def test_sub_pixel_motion_moves_the_centroid_smoothly(r):
    """A disc moved in steps of 0.05 px: its centroid moves by 0.05 px a step, give or take the
    variation of its centroid error (exactly so for sub-pixel discs)."""
    steps = np.arange(0.0, 2.0001, 0.05)
    x = np.array([centroid(disc_coverage((30, 30), (10 + s, 12.37), r))[0] - 10 for s in steps])
    moved = np.diff(x)
    # measured: at most 0.5 below r = 1 (at r = 0.55), 0.23 / r above
    slack = 1e-9 if r <= splat.TINY else (0.6 if r < 1 else 0.3 / r)
    assert np.all(np.abs(moved - 0.05) <= 0.05 * slack + 1e-12), moved


@pytest.mark.parametrize("r", [0.05, 0.2, 0.3, 0.49])
def test_a_sub_pixel_disc_is_its_area_spread_over_the_four_pixels_around_it(r):
    cov = disc_coverage((6, 6), (2.3, 3.8), r)
    expected = np.zeros((6, 6))
    expected[3:5, 2:4] = np.pi * r * r * np.outer([0.2, 0.8], [0.7, 0.3])
    np.testing.assert_allclose(cov, expected, atol=1e-12)


# --- exact colours, untouched pixels, order -------------------------------------------------------

def nearest_and_farthest(shape, centre):
    """Distance from the centre to each pixel's nearest point and to its farthest corner."""
    ys, xs = np.mgrid[0:shape[0], 0:shape[1]].astype(float)
    dx, dy = np.abs(xs - centre[0]), np.abs(ys - centre[1])
    near = np.hypot(np.maximum(dx - 0.5, 0), np.maximum(dy - 0.5, 0))
    return near, np.hypot(dx + 0.5, dy + 0.5)


@pytest.mark.parametrize("r", [0.6, 0.75, 1.3, 3.3, 9.6, 41.0])
def test_inside_pixels_get_exactly_the_colour_and_pixels_out_of_reach_are_untouched(r):
    rng = np.random.default_rng(int(r * 10))
    shape, centres = positions(r, 10, seed=int(r * 10))
    for centre in centres:
        background = rng.integers(0, 256, shape + (3,), dtype=np.uint8)
        canvas = background.copy()
        color = (17, 203, 96)
        draw_discs(canvas, centre, r, color)
        near, far = nearest_and_farthest(shape, centre)
        inside, out = far <= r, near >= r
        assert inside.any() or r < 1
        assert np.all(canvas[inside] == color)
        np.testing.assert_array_equal(canvas[out], background[out])


def test_the_frame_is_blended_by_the_covered_fraction_and_rounded():
    shape, centre, r = (30, 30), (14.37, 15.81), 7.3
    background = np.random.default_rng(5).integers(0, 256, shape + (3,), dtype=np.uint8)
    canvas = background.copy()
    color = np.array([250.0, 3.0, 128.0])
    draw_discs(canvas, centre, r, color)
    c = disc_coverage(shape, centre, r)[..., None]
    expected = background + (color - background) * c
    assert np.abs(canvas - expected).max() <= 0.5 + 1e-9


def test_colours_are_rgb_in_draw_circles_and_later_discs_cover_earlier_ones():
    canvas = np.zeros((40, 60, 3), np.uint8)
    raster.draw_circles(canvas, np.array([[20.0, 20.0], [26.0, 20.0]]), np.array([8.0, 8.0]),
                        np.array([[255, 0, 0], [0, 0, 255]], np.uint8))
    assert tuple(canvas[20, 13]) == (0, 0, 255)       # red, in BGR
    assert tuple(canvas[20, 23]) == (255, 0, 0)       # the blue one, drawn later, on top
    assert tuple(canvas[20, 32]) == (255, 0, 0)


def test_drawing_no_discs_or_rings_changes_nothing():
    canvas = np.random.default_rng(0).integers(0, 256, (20, 30, 3), dtype=np.uint8)
    before = canvas.copy()
    raster.draw_circles(canvas, np.zeros((0, 2)), np.zeros(0), np.zeros((0, 3), np.uint8))
    raster.draw_rings(canvas, np.zeros((0, 2)), np.zeros(0), (255, 255, 255), 1)
    draw_discs(canvas, [], [], (1, 2, 3))
    np.testing.assert_array_equal(canvas, before)


@pytest.mark.parametrize("channels, colour", [(4, (1, 2, 3, 4)), (1, (1,)), (3, (1, 2)), (3, (1, 2, 3, 4))])
def test_discs_and_rings_take_three_channels_and_three_colour_values(channels, colour):
    canvas = np.zeros((10, 10, channels), np.uint8)
    for draw in (lambda: draw_discs(canvas, [[5, 5]], 2.0, colour),
                 lambda: splat.draw_annuli(canvas, [[5, 5]], 2.0, 1.0, colour)):
        with pytest.raises(ValueError, match="3 channels"):
            draw()
    assert not canvas.any()


def test_degenerate_discs_are_skipped():
    canvas = np.zeros((20, 20, 3), np.uint8)
    draw_discs(canvas, [[5, 5], [np.nan, 3], [4, np.inf], [10, 10], [12, 12]], [3, 3, 3, 0.0, -2.0], (9, 9, 9))
    assert canvas[5, 5, 0] == 9
    canvas[:] = 0
    draw_discs(canvas, [[10, 10]], [np.nan], (9, 9, 9))
    assert not canvas.any()


# --- clipping -------------------------------------------------------------------------------------

@pytest.mark.parametrize("r", [0.3, 0.55, 2.2, 7.5, 30.0])
def test_clipped_discs_are_the_same_discs_cut_by_the_canvas(r):
    """On a small canvas, a disc across an edge or corner (or wholly outside) covers what the
    same disc covers of that window on a larger canvas, with its normalization unchanged."""
    margin = int(r) + 4
    for centre in [(-0.3, 9.2), (20.6, 7.1), (6.4, -r + 0.2), (11.1, 15.0 + r - 0.7), (-1.2, -0.9),
                   (19.8, 15.6), (-r - 3.0, 7.0), (10.0, 16.0 + r + 2.0)]:
        small = disc_coverage((15, 20), centre, r)
        large = disc_coverage((15 + 2 * margin, 20 + 2 * margin), np.add(centre, margin), r)
        np.testing.assert_allclose(small, large[margin:-margin, margin:-margin], atol=1e-9)


def test_huge_discs_fill_or_cut_the_canvas():
    canvas = np.zeros((90, 160, 3), np.uint8)
    draw_discs(canvas, [80.3, 44.9], 1e4, (1, 2, 3))
    assert np.all(canvas == (1, 2, 3))
    # an edge 20.3 px from the left of the canvas, nearly straight over its 30 rows
    cov = disc_coverage((30, 40), (20.3 - 1e5, 15.0), 1e5)
    expected = np.clip(20.3 - np.arange(40) + 0.5, 0, 1)
    np.testing.assert_allclose(cov, np.broadcast_to(expected, cov.shape), atol=2e-3)
    canvas[:] = 0
    draw_discs(canvas, [[-5e5, 40.0], [80.0, 1e7]], 4.9e5, (1, 2, 3))    # both end before the canvas
    assert not canvas.any()


def _mixed_discs(n, seed, width=320, height=180):
    """n discs of every kind (sub-pixel, small, large; some across the edges or off the canvas)
    and their colours."""
    rng = np.random.default_rng(seed)
    centres = np.column_stack([rng.uniform(-20, width + 20, n), rng.uniform(-20, height + 20, n)])
    radii = rng.choice([0.2, 0.45, 0.55, 1.4, 3.7, 9.0, 25.0], n)
    return centres, radii, rng.integers(0, 256, (n, 3)).astype(np.float64)


def test_a_clip_draws_exactly_the_clipped_pixels_of_the_whole_drawing():
    """Inside the clip, the bytes of drawing the whole canvas; outside it, nothing: a clipped
    disc keeps its shape and normalization, and it is the same pixel arithmetic."""
    centres, radii, colors = _mixed_discs(2000, 5)
    whole = np.full((180, 320, 3), 40, np.uint8)
    draw_discs(whole, centres, radii, colors)
    splat.draw_annuli(whole, centres[:300], radii[:300], 1.5, (250, 250, 250))
    for clip in [(17, 9, 301, 170), (0, 0, 320, 180), (-50, -3, 40, 500), (100, 60, 101, 61), (30, 30, 30, 90)]:
        clipped = np.full_like(whole, 40)
        draw_discs(clipped, centres, radii, colors, clip=clip)
        splat.draw_annuli(clipped, centres[:300], radii[:300], 1.5, (250, 250, 250), clip=clip)
        left, top, right, bottom = splat.clip_rect(whole, clip)
        inside = np.zeros(whole.shape[:2], bool)
        inside[top:bottom, left:right] = True
        np.testing.assert_array_equal(clipped[inside], whole[inside])
        assert np.all(clipped[~inside] == 40)


def test_the_bytes_do_not_depend_on_how_the_rows_are_split_between_threads():
    """Drawn in horizontal bands (each band every disc, clipped to its rows), in any number of
    bands, down to one row each: the same bytes as in one piece; and draw_discs, which splits
    the rows between threads from bands.BAND_DISCS discs on, gives those bytes too."""
    centres, radii, colors = _mixed_discs(bands.BAND_DISCS + 500, 8)
    one = np.zeros((180, 320, 3), np.uint8)
    filled = splat._read_only(np.full(len(centres), -1.0))

    def discs(canvas, clip):
        centre_args, radius_args, color_args = splat._prepare(canvas, centres, radii, colors)
        splat.splat_rings(canvas, clip, centre_args, radius_args, filled, color_args, 0.5)
    discs(one, (0, 0, 320, 180))
    for rows in ([0, 180], [0, 90, 180], [0, 1, 2, 77, 78, 179, 180], list(range(0, 181, 13)) + [180]):
        banded = np.zeros_like(one)
        for top, bottom in zip(rows[:-1], rows[1:]):
            discs(banded, (0, top, 320, bottom))
        np.testing.assert_array_equal(banded, one)
    assert len(bands._bands((0, 0, 320, 180), len(centres), threads=2)) == 2
    threaded = np.zeros_like(one)
    draw_discs(threaded, centres, radii, colors)
    np.testing.assert_array_equal(threaded, one)
    rings, banded = np.zeros_like(one), np.zeros_like(one)
    ring_args = splat._prepare(rings, centres, radii, (200, 100, 50))
    splat.splat_rings(rings, (0, 0, 320, 180), ring_args[0], ring_args[1], splat._read_only(np.ones(len(centres))),
                      ring_args[2], 0.5)
    for top, bottom in ((0, 61), (61, 180)):   # each clip split into bands again (rings count 15 discs each)
        splat.draw_annuli(banded, centres, radii, 1.0, (200, 100, 50), clip=(0, top, 320, bottom))
    np.testing.assert_array_equal(banded, rings)
    alone = np.zeros_like(one)
    with bands.on_one_thread():     # a video render's drawing: the calling thread only, the same bytes
        assert len(bands._bands((0, 0, 320, 180), len(centres))) == 1
        draw_discs(alone, centres, radii, colors)
    np.testing.assert_array_equal(alone, one)


def _draw_many(seed):
    centres, radii, colors = _mixed_discs(bands.BAND_DISCS + 100, seed)
    canvas = np.zeros((180, 320, 3), np.uint8)
    draw_discs(canvas, centres, radii, colors)
    return hashlib.sha256(canvas.tobytes()).hexdigest()


def test_a_process_forked_after_drawing_in_threads_draws_in_threads_of_its_own():
    """A forked child has none of its parent's pool threads: drawing there must not wait for
    them for ever (a sweep's worker processes are forked from a process that may have drawn)."""
    import multiprocessing
    expected = _draw_many(4)                      # the parent's pool now exists
    with multiprocessing.get_context("fork").Pool(1) as pool:
        assert pool.apply_async(_draw_many, (4,)).get(timeout=60) == expected


# --- rings ----------------------------------------------------------------------------------------

@pytest.mark.parametrize("r,t", [(0.6, 1.0), (1.0, 1.0), (2.5, 1.0), (3.0, 2.0), (6.0, 1.0), (6.0, 2.0),
                                 (20.0, 3.0), (80.0, 2.0)])
def test_a_ring_covers_the_annulus_area(r, t):
    shape, centres = positions(r + t, 8, seed=int(r * 10 + t))
    outer, inner = r + t / 2, r - t / 2
    tolerance = sum(area_tolerance(radius) for radius in (outer, inner))
    for centre in centres:
        cov = ring_coverage(shape, centre, r, t)
        assert cov.min() >= 0 and cov.max() <= 1
        assert abs(cov.sum() - np.pi * (outer ** 2 - inner ** 2)) <= tolerance
        # the annulus is the outer disc's coverage less the inner disc's
        difference = disc_coverage(shape, centre, outer) - disc_coverage(shape, centre, inner)
        np.testing.assert_allclose(cov, np.clip(difference, 0, 1), atol=1e-12)


def test_ring_edge_cases():
    shape, centre = (20, 20), (9.6, 10.2)
    # an inner radius <= 0 is a disc; a negative thickness fills the disc of radius r (cv2's FILLED)
    np.testing.assert_allclose(ring_coverage(shape, centre, 1.5, 4.0), disc_coverage(shape, centre, 3.5))
    np.testing.assert_allclose(ring_coverage(shape, centre, 4.0, -1), disc_coverage(shape, centre, 4.0))
    assert not ring_coverage(shape, centre, 4.0, 0.0).any()
    # both radii under half a pixel: one splat of the annulus's area
    assert ring_coverage(shape, centre, 0.3, 0.2).sum() == pytest.approx(np.pi * (0.4 ** 2 - 0.2 ** 2))
    # an inner radius under half a pixel: the outer disc less a splat
    assert ring_coverage(shape, centre, 0.8, 1.2).sum() == pytest.approx(np.pi * (1.4 ** 2 - 0.2 ** 2))


def test_rings_are_drawn_in_their_colour_with_raster_draw_rings():
    canvas = np.zeros((60, 60, 3), np.uint8)
    raster.draw_rings(canvas, np.array([[30.2, 29.7]]), np.array([20.0]), (255, 214, 102), 3)
    assert tuple(canvas[29, 10]) == (102, 214, 255) and tuple(canvas[30, 30]) == (0, 0, 0)


# --- looks like cv2, and is deterministic ---------------------------------------------------------

def cv2_circles(canvas, centres, radii, colors_rgb):
    """The former drawing: one anti-aliased cv2.circle per disc at 1/16-pixel positions."""
    for (x, y), r, color in zip(np.rint(centres * 16).astype(int).tolist(),
                                np.rint(np.maximum(radii, 0.5) * 16).astype(int).tolist(),
                                np.asarray(colors_rgb)[:, ::-1].tolist()):
        cv2.circle(canvas, (x, y), r, color, -1, cv2.LINE_AA, 4)


def test_discs_look_like_cv2_antialiased_circles():
    """The particles_250 look (8-18 px radii at 720p) on the dark theme, against cv2's drawing of
    the same discs. cv2's anti-aliased fill draws the disc about half a pixel wider in radius
    (its area is 12 % over pi r^2 at r = 8), which the new discs do not: the difference is that
    rim, small over each disc, and centres agree."""
    rng = np.random.default_rng(7)
    n = 40
    centres = np.column_stack([rng.uniform(30, 610, n), rng.uniform(30, 330, n)])
    radii = rng.choice([8.1, 11.8, 16.6], n)
    colors = rng.integers(60, 256, (n, 3)).astype(np.uint8)
    old = np.empty((360, 640, 3), np.uint8)
    old[:] = (28, 20, 18)
    new = old.copy()
    cv2_circles(old, centres, radii, colors)
    raster.draw_circles(new, centres, radii, colors)
    diff = np.abs(old.astype(int) - new.astype(int))
    assert diff.mean() < 2.0                                        # over the frame, in 8-bit levels
    for (x, y), r in zip(centres, radii):
        box = (slice(int(y - r - 2), int(y + r + 3)), slice(int(x - r - 2), int(x + r + 3)))
        assert diff[box].mean() < 16                                # the half-pixel rim, over the disc's box
    # with cv2's disc shrunk by that half pixel, the two agree closely
    shrunk = np.empty_like(old)
    shrunk[:] = (28, 20, 18)
    cv2_circles(shrunk, centres, radii - 0.5, colors)
    assert np.abs(shrunk.astype(int) - new.astype(int)).mean() < 0.6


def test_same_discs_same_bytes_in_this_process_and_another():
    rng = np.random.default_rng(3)
    n = 3000
    centres = np.column_stack([rng.uniform(-20, 340, n), rng.uniform(-20, 200, n)])
    radii = rng.choice([0.3, 0.55, 1.4, 3.7, 9.0, 25.0], n)
    colors = rng.integers(0, 256, (n, 3), dtype=np.uint8)
    frames = []
    for layout in (np.ascontiguousarray, np.asfortranarray):
        canvas = np.zeros((180, 320, 3), np.uint8)
        raster.draw_circles(canvas, layout(centres), layout(radii), layout(colors))
        raster.draw_rings(canvas, layout(centres[:50]), layout(radii[:50]), (255, 255, 255), 1)
        frames.append(canvas)
    np.testing.assert_array_equal(frames[0], frames[1])
    script = (
        "import hashlib, sys, numpy as np\n"
        "from collisim.render import raster\n"
        "rng = np.random.default_rng(3); n = 3000\n"
        "centres = np.column_stack([rng.uniform(-20, 340, n), rng.uniform(-20, 200, n)])\n"
        "radii = rng.choice([0.3, 0.55, 1.4, 3.7, 9.0, 25.0], n)\n"
        "colors = rng.integers(0, 256, (n, 3), dtype=np.uint8)\n"
        "canvas = np.zeros((180, 320, 3), np.uint8)\n"
        "raster.draw_circles(canvas, centres, radii, colors)\n"
        "raster.draw_rings(canvas, centres[:50], radii[:50], (255, 255, 255), 1)\n"
        "print(hashlib.sha256(canvas.tobytes()).hexdigest())\n")
    out = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True, timeout=300)
    assert out.stdout.strip() == hashlib.sha256(frames[0].tobytes()).hexdigest()
