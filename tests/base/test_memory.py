"""kincalc.memory: glibc's malloc keeps freed memory for a batch's next chunk."""

import platform
import subprocess
import sys

import numpy as np

import kincalc
from kincalc.ik import engine

GLIBC = sys.platform.startswith("linux") and platform.libc_ver()[0] == "glibc"


def _in_fresh_process(code: str) -> str:
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True).stdout.strip()


def test_taken_by_glibc_and_tried_once():
    # a fresh process: whether an earlier test has asked already does not matter
    out = _in_fresh_process("from kincalc import memory\n"
                            "print(memory.keep_freed_memory(), memory.keep_freed_memory())")
    assert out == f"{GLIBC} {GLIBC}"


def test_freed_blocks_stay_in_the_heap():
    # glibc: a 2 MB block freed and asked for again comes from the heap, not from mmap
    # (glibc's default for a first block of 128 kB and more); elsewhere nothing changes
    if not GLIBC:
        out = _in_fresh_process("from kincalc import memory; print(memory.keep_freed_memory())")
        assert out == "False"
        return
    code = ("import ctypes\nfrom kincalc import memory\n"
            "libc = ctypes.CDLL(None)\nlibc.malloc.restype = ctypes.c_void_p\n"
            "libc.sbrk.restype = ctypes.c_void_p\nlibc.sbrk.argtypes = (ctypes.c_long,)\n"
            "def heap(p):\n"
            "    return p < libc.sbrk(0)\n"
            "before = libc.malloc(2 << 20)\n"
            "memory.keep_freed_memory()\n"
            "after = libc.malloc(2 << 20)\n"
            "print(heap(before), heap(after))")
    assert _in_fresh_process(code) == "False True"


def test_the_batch_solver_asks_for_it(monkeypatch):
    asked = []
    monkeypatch.setattr(engine, "keep_freed_memory", lambda: asked.append(1) or True)
    robot = kincalc.load_robot("puma560")
    T = robot.fk(np.radians([[10, -40, 170, 20, 30, 40], [0, -90, 180, 0, 0, 0]]))
    robot.ik_batch(T)
    assert asked
