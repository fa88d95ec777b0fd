"""Memory of the machine, for the size checks that stop a build or a run before it cannot fit."""

import os
from pathlib import Path


def available_memory() -> int:
    """Bytes of memory available now (Linux ``/proc/meminfo``; physical memory otherwise)."""
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")
