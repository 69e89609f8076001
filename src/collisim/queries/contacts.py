"""The contacts between a world's bodies where they stand: a query that does not move them."""
import numpy as np

from ..broadphase import find_pairs
from ..core.kinds import shapes_flag
from ..narrowphase.registry import contact_table


def contacts(world, positions=None, angles=None) -> dict:
    """The contacts between the bodies of `world` (at `positions` (n, 2) and `angles` (n,), by
    default the world's own), one per contact point (a face on a face has two): pairs (k, 2) with
    i < j, normals (k, 2) from i to j, depths (k,) (>= 0), points (k, 2) midway between the
    surfaces."""
    positions = world.positions if positions is None else np.asarray(positions, np.float64)
    reach = world.radii[:, None]
    candidates = find_pairs("grid", positions - reach, positions + reach)
    vertices = world.placed_vertices(positions, angles)
    polygons = shapes_flag(world.shapes)
    table = contact_table(world.shapes, positions, world.radii, vertices, world.vertex_start, candidates, polygons)
    return {"pairs": table[:, :2].astype(np.int64), "normals": table[:, 2:4], "depths": table[:, 4],
            "points": table[:, 5:]}
