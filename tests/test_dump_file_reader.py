"""The dump reader's two paths agree: the fast one (pandas's C parser, `records.text_rows`)
reads every value the engines write (%.17g) back bit for bit, as numpy.loadtxt does, and every body
it cannot read goes to numpy's reader, so that a corrupted dump is refused with the same message,
naming the file, the row and the column, as before the fast reader existed."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from records.dump_file import COLUMNS, OBLIQUE_COLUMNS, DumpError, read_dump, write_dump
from records.text_rows import _fast, read_rows

META = {"engine": "test", "case": "x", "impact_velocity": 1.0}
FINITE = st.floats(allow_nan=False, allow_infinity=False, width=64)


@settings(max_examples=60, deadline=None)
@given(arrays(np.float64, st.tuples(st.integers(1, 40), st.sampled_from([len(COLUMNS), len(OBLIQUE_COLUMNS)])),
              elements=FINITE))
def test_every_written_value_reads_back_bit_for_bit(tmp_path_factory, data):
    """Any finite doubles (subnormals, -0.0, 1e308 included) written as the drivers write them read back
    identical (==, and the same sign of zero), through the fast reader, and equal to numpy's reading."""
    path = tmp_path_factory.mktemp("d") / "run.csv"
    write_dump(path, META, data)
    _, columns = read_dump(path)
    got = np.column_stack([columns[c] for c in (COLUMNS if data.shape[1] == len(COLUMNS) else OBLIQUE_COLUMNS)])
    assert np.array_equal(got, data) and np.array_equal(np.signbit(got), np.signbit(data))
    body = path.read_text().splitlines()[len(META) + 2:]
    fast = _fast(body, ",", 0)
    assert fast is not None, "the fast reader refused a clean dump"
    assert np.array_equal(fast, np.loadtxt(body, delimiter=",", ndmin=2))


def test_a_large_dump_of_random_magnitudes_reads_back_bit_for_bit(tmp_path):
    """10^5 values over 60 decades, 10^-30 to 10^30 (an overlap of 1e-12 m beside a force of 1e4 N):
    not one differs from what was written."""
    rng = np.random.default_rng(20261127)
    data = rng.standard_normal((25000, 4)) * 10.0 ** rng.integers(-30, 30, (25000, 4))
    write_dump(tmp_path / "run.csv", META, data)
    _, columns = read_dump(tmp_path / "run.csv")
    assert np.array_equal(np.column_stack([columns[c] for c in COLUMNS]), data)


@pytest.mark.parametrize("row, message", [
    ("5,6,7", "unreadable data: the number of columns changed from 4 to 3 at row 2"),
    ("5,6,7,8,9", "unreadable data: the number of columns changed from 4 to 5 at row 2"),
    ("abc,6,7,8", "unreadable data: could not convert string 'abc' to float64 at row 1, column 1"),
    ("5,6,,8", "unreadable data: could not convert string '' to float64 at row 1, column 3"),
    ('"5",6,7,8', "unreadable data: could not convert string '\"5\"' to float64 at row 1, column 1"),
    ("5,6,7,8,", "unreadable data: the number of columns changed from 4 to 5 at row 2"),
    ("0x10,6,7,8", "unreadable data: could not convert string '0x10' to float64 at row 1, column 1"),
    ("nan,6,7,8", "non-finite value (NaN or inf) in data row 2"),
    ("5,-inf,7,8", "non-finite value (NaN or inf) in data row 2"),
])
def test_a_corrupted_row_is_refused_naming_the_file_row_and_column(tmp_path, row, message):
    """A second data row that is not four numbers: numpy's message (the row, the column), after the file's
    name; NaN and inf are read and then refused by row. The fast reader returns None for each (so that
    the message is numpy's), except an inf, which it reads as numpy does and the same row check refuses
    (NaN it leaves to numpy: it is told no NaN spellings)."""
    path = tmp_path / "run.csv"
    write_dump(path, META, np.array([[0.0, -1e-7, 1.0, 0.0]]))
    path.write_text(path.read_text() + row + "\n")
    with pytest.raises(DumpError) as err:
        read_dump(path)
    assert str(err.value).startswith(f"{path}: {message}"), str(err.value)
    fast = _fast(["0,-1e-07,1,0", row], ",", 0)
    assert fast is None or (message.startswith("non-finite") and not np.isfinite(fast).all())


def test_blank_lines_comments_and_windows_line_ends_read_as_numpy_reads_them(tmp_path):
    """What numpy.loadtxt accepted beside the numbers (a blank line, a '#' comment line or tail, CRLF) the
    fast reader accepts alike, with the same values."""
    body = ["1,2,3,4", "", "# a comment", "5,6,7,8 # tail", "9,10,11,12\r"]
    assert np.array_equal(_fast(body, ",", 0), np.loadtxt(body, delimiter=",", ndmin=2))
    assert _fast(body, ",", 0).shape == (3, 4)


def test_a_whitespace_separated_record_reads_as_numpy_reads_it(tmp_path):
    """LAMMPS's and YADE's records (`engines.finish_run`, `engines.oblique_record`): columns apart by runs
    of spaces or tabs, leading blanks, one header line; the same array as numpy.loadtxt's, bit for bit,
    and a short row refused with numpy's message."""
    rng = np.random.default_rng(7)
    data = rng.standard_normal((500, 8)) * 10.0 ** rng.integers(-20, 20, (500, 8))
    lines = ["step t delta v F vt w1 w2 Ft"] + ["  " + "\t ".join("%.17g" % x for x in row) for row in data]
    raw = tmp_path / "record.txt"
    raw.write_text("\n".join(lines) + "\n")
    got = read_rows(raw, delimiter=None, skiprows=1)
    assert np.array_equal(got, data) and np.array_equal(got, np.loadtxt(raw, skiprows=1, ndmin=2))
    raw.write_text("\n".join(lines[:3] + ["1 2 3"]) + "\n")
    with pytest.raises(ValueError, match="the number of columns changed from 8 to 3"):
        read_rows(raw, delimiter=None, skiprows=1)
