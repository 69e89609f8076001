"""The broad phases' tutorial drawings (render/structures.py): the grid's count tags sit beside
the particles, never on them, and show the engine's own binning."""
import importlib.util

import numpy as np
import pytest

import collisim
from collisim.model.scenefile import available_scenes
from collisim.render import structures
from collisim.render.view import View


@pytest.fixture(scope="module")
def six():
    spec = importlib.util.spec_from_file_location("broadphase_six_tags", available_scenes()["broadphase_six"])
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


@pytest.mark.parametrize("size", [(854, 480), (1920, 1080)])
def test_grid_count_tags_sit_beside_the_particles_and_count_the_engines_cells(six, size):
    trajectory = collisim.simulate(six.grid_chapter().panels[0].scene)
    view = View(six.BOX, (0, 0, *size))
    unit = size[1] / 480
    grid = six.ENGINE_GRID
    for sample in range(0, len(trajectory.times), 10):
        positions = trajectory.positions[sample]
        lo, hi = positions - six.RADII[:, None], positions + six.RADII[:, None]
        members, _ = structures.cell_members(lo, hi, grid)
        counts = [len(m) for m in members]
        canvas = np.zeros((size[1], size[0], 3), np.uint8)
        tags = structures.cell_counts(canvas, view, six.BOX, grid, counts, positions, six.RADII, unit)
        assert len(tags) == sum(c > 0 for c in counts)
        centres, radii = view.to_pixels(positions), view.length(six.RADII)
        for x, y, w, h in tags:
            nearest = np.clip(centres, [x, y], [x + w, y + h])     # the tag's point nearest each centre
            assert (np.hypot(*(nearest - centres).T) > radii).all(), (sample, (x, y, w, h))
        # the tags' numbers are the engine's binning: each body in every cell its box touches
        size_ = 1.0 / grid.cells_per_unit
        first, last = np.floor(lo / size_).astype(int), np.floor(hi / size_).astype(int)
        assert sum(counts) == int(np.prod(last - first + 1, axis=1).sum())
