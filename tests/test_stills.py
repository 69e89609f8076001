"""The README's stills: one per chapter of every tutorial scene at -ql and -qh, at the size of
that quality, small enough to keep in the repository (tools/stills.py makes them)."""
import importlib.util
from pathlib import Path

import collisim
from PIL import Image

ROOT = Path(__file__).resolve().parents[1]


def stills_tool():
    spec = importlib.util.spec_from_file_location("stills_tool", ROOT / "tools" / "stills.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_chapter_of_every_tutorial_scene_has_its_stills_in_the_readme():
    tool = stills_tool()
    readme = (ROOT / "README.md").read_text()
    total = 0
    for name in tool.SCENES:
        plan = collisim.pipeline.plan(collisim.load_scene(name), quality="l")
        assert len(tool.CHAPTERS[name]) == len(plan.chapters), name
        for chapter in range(len(plan.chapters)):
            for quality in tool.QUALITIES:
                path = ROOT / "docs" / "stills" / f"{name}_{chapter + 1}_{quality}.png"
                size = collisim.pipeline.plan(collisim.load_scene(name), quality=quality).size
                assert Image.open(path).size == size, path
                assert f"docs/stills/{path.name}" in readme
                total += path.stat().st_size
    assert total < 8e6
