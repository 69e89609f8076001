"""Arrays for compiled kernels: growable ones for outputs whose size is not known in advance
(candidate pairs, contacts, collision logs: double the capacity when full), a row copy, and the
one sort the kernels use."""
import numpy as np

from .compiling import compiled, kernel


@compiled
def grown(array, size, used=-1):
    """`array` if it has at least `size` rows, else a copy with room for max(size, twice as many).
    Only the first `used` rows are copied (default: all), so a buffer that reserves far more than
    it has filled (a collision log making room for an event per body and wall in every step)
    keeps only what it holds in memory: the pages of the new array past them are never touched."""
    if size <= array.shape[0]:
        return array
    bigger = np.empty((max(size, 2 * array.shape[0]),) + array.shape[1:], array.dtype)
    copy_rows(array, bigger, array.shape[0] if used < 0 else used)
    return bigger


@kernel
def copy_rows(source, target, count):
    """target[:count] = source[:count], for C-contiguous arrays whose rows have the same shape,
    as a plain loop: numba compiles a slice assignment with the message it raises when the shapes
    differ, and that message's string formatting was 3.5 s of a first run's compiling."""
    width = source.size // source.shape[0] if source.shape[0] > 0 else 0
    flat_source, flat_target = source.reshape(source.size), target.reshape(target.size)
    for k in range(count * width):
        flat_target[k] = flat_source[k]


@kernel
def scatter_rows(source, target, order):
    """target[order[k]] = source[k] for every row k of source, for C-contiguous arrays whose rows
    have the same shape (copy_rows, each row to the place `order` gives it)."""
    width = source.size // source.shape[0] if source.shape[0] > 0 else 0
    flat_source, flat_target = source.reshape(source.size), target.reshape(target.size)
    for k in range(source.shape[0]):
        for c in range(width):
            flat_target[order[k] * width + c] = flat_source[k * width + c]


SIGN = np.uint64(1 << 63)


@compiled
def stable_order(keys):
    """The indices (k,) int64 that put the integer keys (k,) in ascending order, equal keys in
    the order given: np.argsort(keys, kind="stable"). The kernels sort with this and
    stable_order_of_floats alone: numba's own argsort compiles a sort of its own for every kind
    and key type asked of it, and this radix sort is faster than its quicksort from a thousand
    keys up (docs/design.md, compiling)."""
    bits = np.empty(keys.shape[0], np.uint64)
    for k in range(keys.shape[0]):
        bits[k] = np.uint64(keys[k]) ^ SIGN   # two's complement -> unsigned, in the same order
    return _radix_order(bits)


@compiled
def stable_order_of_floats(keys):
    """stable_order for float keys without NaN (-0.0 and 0.0 are equal, as for numpy)."""
    values = keys + 0.0   # a copy, C-contiguous, with -0.0 turned into 0.0
    signed = values.view(np.int64)
    bits = np.empty(keys.shape[0], np.uint64)
    for k in range(keys.shape[0]):
        # IEEE-754 -> unsigned in the same order: negative numbers have every bit flipped
        bits[k] = ~np.uint64(signed[k]) if signed[k] < 0 else np.uint64(signed[k]) ^ SIGN
    return _radix_order(bits)


@compiled
def _radix_order(bits):
    """The stable order of the unsigned keys (k,): a counting sort on each byte, least
    significant first, carrying the keys along (a byte all keys share is skipped). The keys are
    the caller's scratch: they end up permuted."""
    n = bits.shape[0]
    order, spare_order = np.arange(n), np.empty(n, np.int64)
    spare_bits, count = np.empty(n, np.uint64), np.empty(257, np.int64)
    for byte in range(8):
        shift = np.uint64(8 * byte)
        first = _digit(bits, 0, shift) if n > 0 else 0
        shared = True
        for k in range(n):
            if _digit(bits, k, shift) != first:
                shared = False
                break
        if shared:
            continue
        count[:] = 0
        for k in range(n):
            count[_digit(bits, k, shift) + 1] += 1
        for digit in range(256):
            count[digit + 1] += count[digit]
        for k in range(n):
            digit = _digit(bits, k, shift)
            at = count[digit]
            spare_order[at], spare_bits[at] = order[k], bits[k]
            count[digit] = at + 1
        order, spare_order = spare_order, order
        bits, spare_bits = spare_bits, bits
    return order


@kernel
def _digit(bits, k, shift):
    """Byte shift / 8 of bits[k], as an int64 (numba would make a float of uint64 + int64)."""
    return np.int64((bits[k] >> shift) & np.uint64(255))


@kernel
def heap_sort(values, first, end):
    """Sort values[first:end] in place in O(m log m) for any input (heapsort: numba's own sort
    compiles a quicksort of its own, 0.6 s on a first run, for sorts that rarely run)."""
    size = end - first
    for root in range(size // 2 - 1, -1, -1):
        _sift_down(values, first, root, size)
    for last in range(size - 1, 0, -1):
        values[first], values[first + last] = values[first + last], values[first]
        _sift_down(values, first, 0, last)


@kernel
def _sift_down(values, first, root, size):
    """Move values[first + root] down the heap of `size` values at `first` until both its
    children are no larger."""
    while 2 * root + 1 < size:
        child = 2 * root + 1
        if child + 1 < size and values[first + child + 1] > values[first + child]:
            child += 1
        if values[first + root] >= values[first + child]:
            return
        values[first + root], values[first + child] = values[first + child], values[first + root]
        root = child
