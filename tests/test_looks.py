"""A video maker's looks: one colour per body (RenderSettings.colors), and a background that picks
text and lines that read on it. Checked on decoded PNG frames."""
import cv2
import numpy as np
import pytest

import collisim
from collisim import palette
from collisim.cli import main
from collisim.pipeline import plan
from collisim.render.timeline import make_players

SIZE = (640, 360)


def rack(colors=None):
    """Fifteen equal balls in a triangle, at rest: colour by radius would make them one colour."""
    rows = [(row, k) for row in range(5) for k in range(row + 1)]
    positions = [(6.0 + 0.9 * row, 4.5 + 0.52 * (2 * k - row)) for row, k in rows]
    world = collisim.World(positions=positions, velocities=np.zeros((15, 2)), radii=0.4, box=(0, 0, 16, 9))
    return collisim.Scene(world=world, fps=30, seconds=0.2, render=collisim.RenderSettings(colors=colors, hud=False))


def centres_px(scene):
    player = make_players(plan(scene, SIZE).chapters[0], SIZE, scene.fps)[0]
    return np.round(player.view.to_pixels(scene.world.positions)).astype(int)


def test_each_body_is_drawn_in_its_own_colour(tmp_path):
    hexes = [f"#{(37 * k) % 256:02x}{(90 + 11 * k) % 256:02x}{(200 - 13 * k) % 256:02x}" for k in range(14)]
    colors = hexes + [(255, 0, 128)]                    # '#RRGGBB' and RGB tuples mixed
    scene = rack(colors)
    image = cv2.imread(str(collisim.render(scene, tmp_path / "rack.png", SIZE, png_frame=0)))
    expected = [palette.parse_color(c) for c in colors]
    for (x, y), rgb in zip(centres_px(scene), expected):
        assert tuple(image[y, x, ::-1]) == rgb


def test_without_colors_a_rack_of_equal_balls_is_one_colour(tmp_path):
    scene = rack()
    image = cv2.imread(str(collisim.render(scene, tmp_path / "rack.png", SIZE, png_frame=0)))
    assert len({tuple(image[y, x]) for x, y in centres_px(scene)}) == 1


@pytest.mark.parametrize("colors, message", [
    (["#ff0000"] * 14, "colors has 14 colours, and the world has 15 bodies"),
    (["#ff0000"] * 14 + ["#ff00"], "colors[14] must look like #1a2b3c"),
    (["#ff0000"] * 14 + [(255, 0, 300)], "colors[14] must be '#RRGGBB' or three whole values in 0..255"),
    ("#ff0000", "colors must be a list of colours"),
])
def test_bad_colors_are_one_line(tmp_path, colors, message):
    with pytest.raises(ValueError, match=message.replace("[", r"\[").replace("(", r"\(")):
        collisim.render(rack(colors), tmp_path / "rack.png", SIZE, png_frame=0)
    assert not (tmp_path / "rack.png").exists()


def hud_ink(image, background):
    """The HUD's pixels (the strip below the box) that differ from the background."""
    strip = image[-22:, :, ::-1].reshape(-1, 3).astype(int)
    return strip[np.abs(strip - background).sum(axis=1) > 30]


@pytest.mark.parametrize("background", ["#ffffff", "#f0e68c", "#000000", "#203040"])
def test_a_background_picks_text_that_reads_on_it(tmp_path, monkeypatch, background):
    monkeypatch.chdir(tmp_path)
    argv = ["render", "single_bounce", "-s", "--size", "854x480", "--no-progress", "--background", background]
    assert main([*argv, "-o", "still"]) == 0
    image = cv2.imread(str(tmp_path / "renders/single_bounce/still.png"))
    rgb = palette.parse_color(background)
    assert tuple(image[0, 0, ::-1]) == rgb
    ink = hud_ink(image, rgb)
    # the strongest of the HUD's pixels (its letters' cores, in the theme's dim text): at least
    # WCAG's 3:1, and more than the other theme's
    chosen = max(palette.contrast(p, rgb) for p in ink)
    assert len(ink) > 100 and chosen >= 3.0
    other = "light" if palette.theme_for(rgb) == "dark" else "dark"
    assert main([*argv, "--theme", other, "-o", "other"]) == 0          # an explicit theme still wins
    ink = hud_ink(cv2.imread(str(tmp_path / "renders/single_bounce/other.png")), rgb)
    assert np.abs(ink - palette.THEMES[other].dim_text).sum(axis=1).min() <= 6   # its HUD colour, as asked
    assert max(palette.contrast(p, rgb) for p in ink) < chosen
