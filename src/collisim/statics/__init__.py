"""Static geometry: the box walls, thin segments, and the index that finds the segments near a body."""
from .segment_index import SegmentIndex, build_segment_index, segments_near, segments_near_box

__all__ = ["SegmentIndex", "build_segment_index", "segments_near", "segments_near_box"]
