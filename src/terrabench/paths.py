"""Output paths checked before any work: one line naming the path and what is wrong.

Nothing here creates anything: a command checks its ``--out`` first, then runs, then writes.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path


def _nearest_existing(path: Path) -> Path:
    p = path.absolute()
    while not p.exists() and p != p.parent:
        p = p.parent
    return p


def _writable_dir(d: Path) -> bool:
    """Whether a file can be made in folder ``d`` (tried: permission bits do not bind root, and a
    read-only or virtual file system such as /proc says no only when asked)."""
    if not (d.is_dir() and os.access(d, os.W_OK | os.X_OK)):
        return False
    try:
        with tempfile.TemporaryFile(dir=d):
            return True
    except OSError:
        return False


def check_out_file(path: str | Path, flag: str = "--out", suffixes: tuple[str, ...] | None = None) -> Path:
    """``path`` as a file that can be written (its folder is created later if missing).

    Raises:
        ValueError: it is a folder, has a suffix outside ``suffixes``, or neither it nor the
            nearest existing folder above it can be written.
    """
    out = Path(path)
    if suffixes is not None and out.suffix.lower() not in suffixes:
        raise ValueError(f"{flag} {str(out)!r}: unknown suffix {out.suffix or '(none)'!r}; "
                         f"valid: {', '.join(suffixes)}")
    if out.is_dir():
        raise ValueError(f"{flag} {str(out)!r} is a folder; give a file name")
    if out.exists():
        if not os.access(out, os.W_OK):
            raise ValueError(f"{flag} {str(out)!r} exists and is not writable")
        return out
    base = _nearest_existing(out.parent)
    if not base.is_dir():
        raise ValueError(f"{flag} {str(out)!r} cannot be created: {str(base)!r} is a file, not a folder")
    if not _writable_dir(base):
        raise ValueError(f"{flag} {str(out)!r} cannot be created: {str(base)!r} is not writable")
    return out


def check_out_dir(path: str | Path, flag: str = "--out") -> Path:
    """``path`` as a folder that can be created or written into (nothing is created here).

    Raises:
        ValueError: it is an existing file, or neither it nor the nearest existing folder above
            it can be written.
    """
    out = Path(path)
    if out.exists() and not out.is_dir():
        raise ValueError(f"{flag} {str(out)!r} is an existing file; give a folder")
    base = _nearest_existing(out)
    if not base.is_dir():
        raise ValueError(f"{flag} {str(out)!r} cannot be created: {str(base)!r} is a file, not a folder")
    if not _writable_dir(base):
        raise ValueError(f"{flag} {str(out)!r} cannot be written: {str(base)!r} is not writable")
    return out
