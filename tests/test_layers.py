"""The layers point one way (docs/architecture.md): every import in the package, at the top of a
module or inside a function, read from the sources and checked against the layering rules."""
import ast
import subprocess
import sys
from pathlib import Path

import collisim

PACKAGE = Path(collisim.__file__).parent


def imports_by_module() -> dict:
    """{module: {imported collisim module}} for every module of the package, every import
    statement included (those inside functions too: a lazy import hides a cycle, it does not
    remove it)."""
    found = {}
    for path in PACKAGE.rglob("*.py"):
        parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
        is_package = parts[-1] == "__init__"
        name = ".".join(parts[:-1] if is_package else parts)
        here = name.split(".") if is_package else name.split(".")[:-1]
        targets = set()
        for node in ast.walk(ast.parse(path.read_text())):
            if isinstance(node, ast.ImportFrom):
                base = here[:len(here) - node.level + 1] if node.level else []
                module = ".".join(base + ([node.module] if node.module else []))
                targets |= {module} if node.module or not node.level else {f"{module}.{a.name}" for a in node.names}
            elif isinstance(node, ast.Import):
                targets |= {a.name for a in node.names}
        found[name] = {t for t in targets if t == "collisim" or t.startswith("collisim.")}
    return found


def layer(module: str) -> str:
    """The package (or top-level module) of collisim a module belongs to."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else "collisim"


IMPORTS = imports_by_module()


def package_edges() -> dict:
    edges = {}
    for module, targets in IMPORTS.items():
        for target in targets:
            if layer(target) != layer(module) and layer(module) != "collisim":
                edges.setdefault(layer(module), set()).add(layer(target))
    return edges


def test_the_core_imports_nothing_of_collisim_above_it():
    outside = {(m, t) for m, ts in IMPORTS.items() if layer(m) == "core" for t in ts if layer(t) != "core"}
    assert not outside


def test_the_model_imports_only_the_core_and_the_plain_modules_beside_it():
    # shapes.py (polygon constructors) and palette.py (colours) import nothing but the core
    allowed = {"core", "model", "shapes", "palette"}
    assert {layer(t) for m, ts in IMPORTS.items() if layer(m) in allowed - {"core", "model"} for t in ts} <= {"core"}
    assert {(m, t) for m, ts in IMPORTS.items() if layer(m) == "model" for t in ts if layer(t) not in allowed} == set()


def test_no_package_imports_one_that_imports_it_back():
    edges = package_edges()

    def reaches(start, goal, seen=()):
        return any(step == goal or (step not in seen and reaches(step, goal, seen + (step,)))
                   for step in edges.get(start, ()))
    assert [package for package in edges if reaches(package, package)] == []


def test_the_engine_and_what_it_uses_never_import_measurement_rendering_or_the_command_line():
    above = {"analysis", "render", "pipeline", "cli", "notebook", "bridges", "io"}
    below = {"engine", "broadphase", "narrowphase", "response", "statics", "queries", "model", "core"}
    assert {(m, t) for m, ts in IMPORTS.items() if layer(m) in below for t in ts if layer(t) in above} == set()


def test_importing_collisim_loads_neither_dask_nor_matplotlib_nor_the_references():
    code = ("import sys, collisim, collisim.cli; "
            "print(sorted(m for m in ('dask', 'distributed', 'matplotlib', 'pymunk', 'Box2D') if m in sys.modules))")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert done.stdout.strip() == "[]"
