"""The allocator setting of toonface's processes (common.memory), seen in glibc's own counters."""

import platform
import subprocess
import sys

import pytest

pytestmark = pytest.mark.skipif(platform.libc_ver()[0] != "glibc", reason="mallopt and mallinfo2 are glibc's")

_HEAP_AFTER_FREEING = """
import ctypes, sys
from common.memory import keep_freed_memory

class MallInfo2(ctypes.Structure):
    _fields_ = [(name, ctypes.c_size_t) for name in
                ("arena", "ordblks", "smblks", "hblks", "hblkhd", "usmblks", "fsmblks", "uordblks", "fordblks",
                 "keepcost")]

libc = ctypes.CDLL("libc.so.6")
libc.malloc.restype, libc.malloc.argtypes = ctypes.c_void_p, [ctypes.c_size_t]
libc.free.argtypes = [ctypes.c_void_p]
libc.mallinfo2.restype = MallInfo2
kept = keep_freed_memory() if sys.argv[1] == "keep" else False
blocks = [libc.malloc(64 << 10) for _ in range(400)]  # 25 MB in blocks below the mmap threshold: the heap
for block in blocks:
    libc.free(block)
heap = libc.mallinfo2().arena >> 20  # the heap's size after all of it was freed, MB
before = libc.mallinfo2().hblks  # blocks in mappings of their own
big = libc.malloc(200 << 20)  # one long take's array: above glibc's largest dynamic mmap threshold (32 MB)
mapped = libc.mallinfo2().hblks - before
libc.free(big)
print(int(kept), heap, mapped, libc.mallinfo2().arena >> 20)
"""


@pytest.mark.parametrize("mode", ["keep", "default"])
def test_freed_memory_stays_in_the_heap_only_when_asked(mode):
    out = subprocess.run([sys.executable, "-c", _HEAP_AFTER_FREEING, mode], capture_output=True, text=True,
                         check=True).stdout.split()
    kept, heap_mb, mapped, heap_after_big_mb = map(int, out)
    if mode == "keep":
        assert kept == 1 and heap_mb >= 64  # the 25 MB freed, and the 64 MB pad the heap grew by, kept
        assert mapped == 0 and heap_after_big_mb >= 200  # the 200 MB block came from the heap, and stayed there
    else:
        assert heap_mb < 16  # trimmed back as the blocks were freed
        assert mapped == 1 and heap_after_big_mb < 16  # a mapping of its own, given back when freed
