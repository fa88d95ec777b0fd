"""Output paths: checked before any work, written by one run at a time, with the usual permissions.

A long computation must not end in an ``OSError`` because its output folder is read-only, and two
runs writing one file must not both report it as theirs. :func:`claim_output` checks a target
before anything is computed (the folder exists or can be made, and a file can be created in it)
and holds a lock file next to the target until the run ends; a second run asking for the same
target while the first is alive is refused by name. A lock left by a run that died (its process
no longer exists) is taken over. :func:`usual_mode` gives a file written through a temporary
file the permissions a plain ``open()`` would have (``0666 & ~umask``).
"""

from __future__ import annotations

import contextlib
import os
import socket
from pathlib import Path

from rubrotor.errors import InputError

__all__ = ["check_output", "claim_output", "usual_mode", "lock_path"]


def usual_mode(path: str | os.PathLike) -> None:
    """Set ``path``'s permissions to those of a newly created file (``0666 & ~umask``).

    Parameters
    ----------
    path : path-like
        A file made by ``tempfile.mkstemp`` (mode 0600) that is about to be renamed onto
        its target.
    """
    umask = os.umask(0o022)
    os.umask(umask)
    os.chmod(path, 0o666 & ~umask)


def lock_path(path: str | os.PathLike) -> Path:
    """The lock file of an output ``path``: ``.NAME.lock`` in the same folder."""
    p = Path(path)
    return p.parent / f".{p.name}.lock"


def _existing_ancestor(p: Path) -> Path:
    p = p.absolute()
    while not p.exists() and p != p.parent:
        p = p.parent
    return p


def check_output(path: str | os.PathLike, field: str = "--out", *, folder: bool = False) -> Path:
    """Refuse, before any work, an output that cannot be written.

    Parameters
    ----------
    path : path-like
        The target file (or folder when ``folder``).
    field : str
        The option or argument that named it, for the message.
    folder : bool
        ``path`` is a folder to write files into (made if missing).

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    InputError
        A parent is a file, or no file can be created where the output goes (read-only folder,
        no permission); the message names ``field``, the path and the reason.
    """
    p = Path(path)
    if folder and p.exists() and not p.is_dir():
        raise InputError(field, str(path), "a directory (this is a file)")
    where = p if folder else p.parent
    base = _existing_ancestor(where)
    if not base.is_dir():
        raise InputError(field, str(path), f"a path inside a folder ({base} is not a folder)")
    probe = base / f".rubrotor-probe-{os.getpid()}"
    try:
        fd = os.open(probe, os.O_CREAT | os.O_EXCL | os.O_WRONLY, 0o600)
        os.close(fd)
        os.remove(probe)
    except OSError as exc:
        raise InputError(
            field, str(path), f"a path in a writable folder ({base}: {exc.strerror})"
        ) from None
    return p


def _holder(lock: Path) -> int | None:
    """The pid of a live process on this host holding ``lock``, or None (stale or unreadable)."""
    try:
        pid_text, _, host = lock.read_text().partition(" ")
        pid = int(pid_text)
    except (OSError, ValueError):
        return None
    if host.strip() != socket.gethostname():
        return pid  # a run on another host sharing the folder: cannot check, assume alive
    if pid == os.getpid():
        return None  # left by this process (the lock is removed when a claim ends)
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return None
    except PermissionError:
        return pid
    return pid


def _acquire(lock: Path, field: str, path) -> int:
    """Open ``lock`` and take an exclusive ``flock`` on it: the descriptor, or
    ``InputError`` naming the live process that holds it.

    The kernel releases the lock when its process dies, however it dies, so a lock file left
    behind by a killed run is free to take, and there is no window in which a lock being
    written looks stale (an empty file, seen by 1 of 14 simultaneous starts when liveness was
    read from the file's content). A lock taken on a file another run removed meanwhile (a
    different inode at the path) is let go and taken again.
    """
    import fcntl

    for _ in range(16):
        fd = os.open(lock, os.O_CREAT | os.O_RDWR, 0o644)
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            os.close(fd)
            pid = _holder(lock)
            who = f"process {pid} is" if pid is not None else "another run is"
            raise InputError(field, str(path), f"a path no other run is writing ({who} writing "
                             f"it; its lock is {lock})") from None  # fmt: skip
        try:
            same = os.stat(lock).st_ino == os.fstat(fd).st_ino
        except FileNotFoundError:
            same = False
        if same:
            os.ftruncate(fd, 0)
            os.write(fd, f"{os.getpid()} {socket.gethostname()}".encode())
            return fd
        os.close(fd)  # removed by the run that held it: take the new file
    raise InputError(field, str(path), f"a path no other run is writing (lock {lock})")


@contextlib.contextmanager
def claim_output(path: str | os.PathLike, field: str = "--out", *, folder: bool = False):
    """Check ``path`` (:func:`check_output`) and hold its lock file while the body runs.

    The lock ``.NAME.lock`` (see :func:`lock_path`) is held with an exclusive ``flock``
    (``_acquire``) and holds ``"PID HOSTNAME"`` (for the message); it is removed when the
    body ends, however it ends. A lock file left by a run that died is free (the kernel
    released its lock) and taken over.

    Parameters
    ----------
    path : path-like
        The target file (or folder when ``folder``; its lock then sits inside it).
    field : str
        The option or argument that named it, for the message.
    folder : bool
        ``path`` is a folder (made if missing).

    Yields
    ------
    Path
        ``path``.

    Raises
    ------
    InputError
        ``path`` cannot be written, or another live run is writing it (its pid is named).
    """
    p = check_output(path, field, folder=folder)
    where = p if folder else p.parent
    where.mkdir(parents=True, exist_ok=True)
    lock = where / ".rubrotor.lock" if folder else lock_path(p)
    fd = _acquire(lock, field, path)
    try:
        yield p
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.remove(lock)  # before unlocking: a run that opened it sees another inode, retries
        os.close(fd)
