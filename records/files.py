"""The file helpers every layer above uses: a file's sha256, and writes that appear only whole
(`write_atomically` for bytes and text, `save_figure` for a matplotlib figure)."""

from __future__ import annotations

import hashlib
import os
from pathlib import Path


def file_sha256(path) -> str:
    """The sha256 of a file's bytes, as hex.

    Parameters
    ----------
    path : str or os.PathLike
        The file.
    """
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def _temporary(path: Path) -> Path:
    """The hidden temporary file beside `path` that a write goes to first ('.<name>.<pid>.part'). The
    process id keeps two writers of one file apart (two jobs that start together both mark the
    study's verdict stale): each replaces the file whole, the last one's stays."""
    return path.with_name(f".{path.name}.{os.getpid()}.part")


def _replace_with(path: Path, write) -> None:
    """Call `write(tmp)` on the temporary file of `path`, then move it onto `path`; when the write
    fails (a full disk, a read-only folder, an error while drawing) the temporary file goes and the
    error is raised, so that `path` is the old file or none, never a part of the new one. An
    OSError names `path`, not the temporary file ("[Errno 30] Read-only file system:
    'results/steel/plots/timestep.png'")."""
    tmp = _temporary(path)
    try:
        write(tmp)
        os.replace(tmp, path)
    except BaseException as err:
        try:
            tmp.unlink(missing_ok=True)
        except OSError:  # a read-only folder: nothing was written there either
            pass
        if isinstance(err, OSError) and err.errno is not None:
            raise type(err)(err.errno, err.strerror, str(path)) from err
        raise


def write_atomically(path, data: bytes | str) -> None:
    """Write `path` so that a reader sees the old file or the whole new one, never a part: the
    data go to a hidden temporary file beside it ('.<name>.<pid>.part'), which then replaces it;
    a write that fails leaves no temporary file behind.

    Parameters
    ----------
    path : str or os.PathLike
        The file to write.
    data : bytes or str
        Its whole new content (text is written as UTF-8).
    """
    path = Path(path)
    _replace_with(path, lambda tmp: tmp.write_bytes(data.encode() if isinstance(data, str) else data))


def set_margins(fig, left: float, right: float, top: float, bottom: float, wspace: float = 0.2,
                hspace: float = 0.2) -> None:
    """Place a figure's grid of axes by margins in inches, in place of `Figure.tight_layout`.

    tight_layout draws the figure once to measure every tick label and title, then lays it out
    (a quarter to a third of a report figure's seconds on log axes); a fixed grid of panels
    needs no measuring: its margins are set once, in inches, so that they stay the same whatever
    the figure's size. The fractions given to `Figure.subplots_adjust` are

        left_f = left / W,  right_f = 1 - right / W,  top_f = 1 - top / H,  bottom_f = bottom / H,

    with W x H the figure's size [in].

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    left, right, top, bottom : float
        The margins [in]: room for the y tick labels and label, the titles and suptitle, the
        x tick labels and label, and anything placed outside the axes (a figure legend).
    wspace, hspace : float
        The gaps between panels as fractions of the mean panel width and height [-].
    """
    width, height = fig.get_size_inches()
    fig.subplots_adjust(left=left / width, right=1 - right / width, top=1 - top / height, bottom=bottom / height,
                        wspace=wspace, hspace=hspace)


def save_figure(fig, path, **savefig_kwargs) -> None:
    """`fig.savefig(path, **savefig_kwargs)`, atomically: drawn into a hidden temporary file beside
    `path` (in the format of `path`'s suffix, e.g. png), which then replaces it. A save that fails
    (a full disk: matplotlib has written part of the image) leaves neither `path` nor a temporary
    file, instead of a truncated picture under the real name. Every figure of the project is saved
    through this.

    Parameters
    ----------
    fig : matplotlib.figure.Figure
        The figure.
    path : str or Path
        Where it goes; its suffix gives the format unless `savefig_kwargs` has ``format``.
    **savefig_kwargs
        Passed to `Figure.savefig` (dpi, bbox_inches, ...).
    """
    path = Path(path)
    kwargs = {"format": path.suffix.lstrip(".").lower() or None, **savefig_kwargs}
    _replace_with(path, lambda tmp: fig.savefig(tmp, **kwargs))
