"""How a toonface process keeps the memory it frees.

Cleaning and mapping a take allocate many whole-take arrays (a 30 s take of 32 markers at
120 Hz is 2.8 MB an array) and free them at once. glibc's allocator hands such blocks back to
the kernel as soon as they are freed (from their own mappings, or by trimming the top of the
heap), so the next array of that size starts again on fresh pages, each zeroed by a page fault.
On a virtual machine that returns freed pages to its host (Firecracker's free page reporting, for
one) a fault costs several microseconds, and the faults took about a fifth of the time of
cleaning and mapping a take. :func:`keep_freed_memory` asks the allocator to keep up to a set
amount of freed memory at the top of its heap for the next arrays instead.
"""

from __future__ import annotations

import ctypes

_M_TOP_PAD = -2  # mallopt's parameter numbers (glibc's malloc.h)


def keep_freed_memory(megabytes: int = 64) -> bool:
    """Ask glibc's allocator to keep up to ``megabytes`` of freed memory for reuse (``M_TOP_PAD``).

    The heap then grows and shrinks in steps of that size: a process's resident memory may stay
    that much above what it uses, and whole-take arrays reuse pages already touched. Called by
    the ``toonface`` command and the batch workers, not on import: a program using the library
    decides for itself. Returns whether the setting was made (False where the C library is not
    glibc).
    """
    try:  # the process's own symbols: no search for the C library (find_library runs ldconfig)
        mallopt = ctypes.CDLL(None).mallopt
    except (OSError, AttributeError):  # not glibc (musl has no mallopt; macOS and Windows neither)
        return False
    mallopt.argtypes, mallopt.restype = [ctypes.c_int, ctypes.c_int], ctypes.c_int
    return bool(mallopt(_M_TOP_PAD, int(megabytes) << 20))
