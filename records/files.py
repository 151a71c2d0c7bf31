"""The file helpers every layer above uses: a file's sha256, and a write that appears only whole."""

from __future__ import annotations

import hashlib
import os
from pathlib import Path


def file_sha256(path) -> str:
    """The sha256 of a file's bytes, as hex."""
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def write_atomically(path, data: bytes | str) -> None:
    """Write `path` so that a reader sees the old file or the whole new one, never a part: the
    data go to a hidden temporary file beside it ('.<name>.<pid>.part'), which then replaces it.
    The process id keeps two writers of one file apart (two jobs that start together both mark
    the study's verdict stale): each replaces the file whole, the last one's stays."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.part")
    tmp.write_bytes(data.encode() if isinstance(data, str) else data)
    os.replace(tmp, path)
