"""Small pure kernels that every path shares (the discrete step, the event-driven method, the
player's overlays): the box, segments, the line of centres of two circles, times of impact,
and polynomial roots. Each formula is written here once."""
