"""The rasterizer puts each circle where the world-to-pixel transform says, with y up."""
import numpy as np
import pytest

import collisim
from collisim.pipeline import scene_chapters
from collisim.render.timeline import draw_frame, make_players
from collisim.render.view import View


def test_view_fits_the_box_and_flips_y():
    view = View((0, 0, 16, 9), (0, 0, 1280, 720), margin=0.0)
    np.testing.assert_allclose(view.to_pixels([[0, 0], [16, 9], [8, 4.5]]), [[0, 720], [1280, 0], [640, 360]])
    assert view.scale == pytest.approx(80.0)


def blob_centroids(image, colors):
    """Centroid of the pixels closest to each colour (weighted by coverage along the green channel)."""
    centroids = []
    for color in colors:
        rgb = image[:, :, ::-1].astype(float)
        distance = np.linalg.norm(rgb - np.asarray(color, float), axis=2)
        mask = distance < 60
        ys, xs = np.nonzero(mask)
        centroids.append((xs.mean(), ys.mean()))
    return np.array(centroids)


def test_circle_centroids_land_within_half_a_pixel_of_the_transform():
    rng = np.random.default_rng(3)
    positions = np.array([[2.37, 7.61], [12.913, 1.77], [8.05, 4.4321]])  # y up: the first is high
    colors = [(255, 80, 80), (80, 255, 80), (80, 120, 255)]
    world = collisim.World(positions=positions + rng.uniform(-0.01, 0.01, (3, 2)), radii=[0.6, 0.9, 1.2],
                           box=(0, 0, 16, 9), colors=colors)
    scene = collisim.Scene(world=world, fps=30, seconds=1.0,
                           render=collisim.RenderSettings(hud=False, flash=False))
    size = (800, 450)
    players = make_players(scene_chapters(scene)[0], size, scene.fps)
    canvas = np.zeros((size[1], size[0], 3), np.uint8)
    draw_frame(canvas, players, 0)
    expected = players[0].view.to_pixels(world.positions)
    measured = blob_centroids(canvas, colors)
    assert np.all(np.abs(measured - expected) < 0.5), (measured, expected)
    assert measured[0, 1] < measured[1, 1]   # higher in the world is higher in the image
