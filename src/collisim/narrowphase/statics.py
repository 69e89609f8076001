"""A circle against the static geometry: thin segments (found through the static index)."""
import numpy as np

from ..core.arrays import grown
from ..core.compiling import compiled, kernel
from ..core.geometry.segment import segment_contact
from ..statics.segment_index import build_segment_index, segments_near


@kernel
def circle_segment(positions, radii, i, segments, s):
    """The contact of circle i with segment s as (nx, ny, depth, qx, qy): the unit normal from
    the segment's closest point q towards the centre, the overlap depth (negative when apart)
    and q."""
    nx, ny, distance, qx, qy, _ = segment_contact(positions[i, 0], positions[i, 1], segments[s])
    return nx, ny, radii[i] - distance, qx, qy


@compiled
def segment_contacts(positions, radii, segments, index, contacts, near, within):
    """Every (body, segment) pair that touches, or is apart by at most `within` times the body's
    radius, bodies in index order, each body's segments in index order. contacts: a (c, 2)
    int64 buffer (grown and returned); near: (m,) int64 scratch. Returns (contacts, count)."""
    count = 0
    for i in range(positions.shape[0]):
        r = radii[i] * (1.0 + within)
        found = segments_near(index, positions[i, 0] - r, positions[i, 1] - r, positions[i, 0] + r,
                              positions[i, 1] + r, near)
        for k in range(found):
            s = near[k]
            if circle_segment(positions, radii, i, segments, s)[2] >= -within * radii[i]:
                contacts = grown(contacts, count + 1)
                contacts[count, 0], contacts[count, 1] = i, s
                count += 1
    return contacts, count


def touching_segments(positions, radii, segments, box) -> tuple:
    """Which circles touch which segments, outside a run (validation, tools): pairs (k, 2)
    body, segment, and their depths (k,), through a static index built for the call."""
    found, count = segment_contacts(positions, radii, segments, build_segment_index(segments, box),
                                    empty_contacts(), np.empty(len(segments), np.int64), 0.0)
    pairs = found[:count].copy()
    depths = np.array([circle_segment(positions, radii, i, segments, s)[2] for i, s in pairs])
    return pairs, depths


@compiled
def empty_contacts():
    """A (16, 2) int64 buffer for segment_contacts to grow."""
    return np.empty((16, 2), np.int64)
