"""Numeric text tables (an engine's per-step record, a dump's rows) read fast, and read exactly.

`read_rows` reads with pandas's C parser, 2.5 to 3 times numpy.loadtxt's speed on the study's files
(a LAMMPS oblique job's ~100 dumps of up to 10^5 rows took 5.7 s with loadtxt, 1.6 s so), and leaves
to numpy.loadtxt every table that parser refuses, so that a bad table gets numpy's message, which
names the row and the column. pandas 3's parser rounds correctly: a value written with %.17g reads
back bit for bit, as numpy's does (tests/test_dump_file_reader.py). Only what both readers accept
takes the fast path: no quoting, no NaN spelled out (numpy reads it, and the caller refuses the row),
'#' starts a comment, blank lines are skipped.
"""

from __future__ import annotations

import csv
import io
import os

import numpy as np


def read_rows(source, delimiter: str | None = ",", skiprows: int = 0) -> np.ndarray:
    """A table of numbers as an N x M float array (N >= 0), as numpy.loadtxt(source, delimiter=delimiter,
    skiprows=skiprows, ndmin=2) reads it.

    Parameters
    ----------
    source : str, os.PathLike or list of str
        A file, or its lines (without line ends).
    delimiter : str or None
        The field separator; None: runs of whitespace.
    skiprows : int
        Lines to skip first (a header).

    Raises
    ------
    ValueError
        numpy.loadtxt's, for a table it cannot read (a field that is no number, a row of another
        width).
    OSError
        The file cannot be read.
    """
    fast = _fast(source, delimiter, skiprows)
    if fast is not None:
        return fast
    return np.loadtxt(source, delimiter=delimiter, skiprows=skiprows, ndmin=2)


def _fast(source, delimiter, skiprows) -> np.ndarray | None:
    """`read_rows` by pandas's C parser, or None where it refuses the table (numpy then reads it)."""
    import pandas as pd  # here, not at the top: the engine jobs that write records import this module too

    handle = io.StringIO("\n".join(source)) if isinstance(source, list) else os.fspath(source)
    try:
        data = pd.read_csv(handle, header=None, dtype=float, engine="c", na_filter=False, comment="#",
                           quoting=csv.QUOTE_NONE, skiprows=skiprows,
                           **({"sep": r"\s+"} if delimiter is None else {"sep": delimiter}))
    except (ValueError, pd.errors.EmptyDataError):  # ParserError is a ValueError
        return None
    values = data.to_numpy()
    return values if values.ndim == 2 and values.shape[0] > 0 else None
