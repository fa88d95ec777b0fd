"""Memory of the machine, for the size checks that stop a build or a run before it cannot fit."""

import os
from pathlib import Path


def available_memory() -> int:
    """Bytes of memory available now (Linux ``/proc/meminfo``; physical memory otherwise),
    no more than what this process's address-space limit (``ulimit -v``) leaves."""
    return min(_machine_memory(), _address_space_left())


def _machine_memory() -> int:
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable:"):
                return int(line.split()[1]) * 1024
    except OSError:
        pass
    return os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES")


def _address_space_left() -> int:
    """Bytes the ``RLIMIT_AS`` soft limit leaves above the process's virtual size (a very
    large number without a limit or where it cannot be read)."""
    unlimited = 2**62
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
        if soft in (resource.RLIM_INFINITY, -1):
            return unlimited
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmSize:"):
                return max(0, soft - int(line.split()[1]) * 1024)
        return soft
    except (ImportError, OSError, ValueError):
        return unlimited
