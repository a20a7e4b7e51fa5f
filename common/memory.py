"""How a toonface process keeps the memory it frees.

Cleaning and mapping a take allocate many whole-take arrays (a 30 s take of 32 markers at
120 Hz is 2.8 MB an array) and free them at once. glibc's allocator hands such blocks back to
the kernel as soon as they are freed (from their own mappings, or by trimming the top of the
heap), so the next array of that size starts again on fresh pages, each zeroed by a page fault.
On a virtual machine that returns freed pages to its host (Firecracker's free page reporting, for
one) a fault costs several microseconds, and the faults took about a fifth of the time of
cleaning and mapping a take. :func:`keep_freed_memory` asks the allocator to keep freed memory
for the next arrays instead: blocks up to a set size come from the heap rather than from mappings
of their own (glibc maps anything above 32 MB afresh however often it is freed and asked for
again: an hour's take is 330 MB an array, and its faults took 13 of the 32 s it took to map), and
up to that much freed at the top of the heap is kept.
"""

from __future__ import annotations

import ctypes

_M_TRIM_THRESHOLD, _M_TOP_PAD, _M_MMAP_THRESHOLD = -1, -2, -3  # mallopt's parameter numbers (glibc's malloc.h)


def keep_freed_memory(megabytes: int = 1024, pad_megabytes: int = 64) -> bool:
    """Ask glibc's allocator to keep freed memory for reuse.

    Blocks up to ``megabytes`` come from the heap (``M_MMAP_THRESHOLD``), up to ``megabytes`` freed
    at its top stays there (``M_TRIM_THRESHOLD``), and the heap grows in steps of
    ``pad_megabytes`` (``M_TOP_PAD``): whole-take arrays reuse pages already touched. A process's
    resident memory may then stay up to ``megabytes`` above what it uses (its peak, for a program
    that maps one take and ends). Called by the ``toonface`` command and the batch workers, not on
    import: a program using the library decides for itself. Returns whether the settings were
    made (False where the C library is not glibc).
    """
    try:  # the process's own symbols: no search for the C library (find_library runs ldconfig)
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError):  # not glibc (musl has no mallopt; macOS and Windows neither)
        return False
    mallopt.argtypes, mallopt.restype = [ctypes.c_int, ctypes.c_int], ctypes.c_int
    size = min(int(megabytes) << 20, 2**31 - 1)  # mallopt takes an int
    return all([mallopt(_M_MMAP_THRESHOLD, size), mallopt(_M_TRIM_THRESHOLD, size),
                mallopt(_M_TOP_PAD, int(pad_megabytes) << 20)])
