"""YAML read as plain data, strictly, so that a file cannot say one thing and mean another.

`scan_plain_yaml` walks the YAML events once and refuses, naming the field and the line:
duplicated keys, keys that are not names, anchors and aliases, explicit tags, YAML 1.1 spellings
of numbers and booleans (0.3_0, 010, 1:30, yes), nesting deeper than MAX_DEPTH and several
documents. `read_utf8` reads a small UTF-8 file: a regular file (not a device such as
/dev/zero, a FIFO or a directory) no larger than a limit, both checked before a byte is read.
Every refusal is a `CaseError` (or the error class the caller names).
"""

from __future__ import annotations

import os
import re
import stat
from pathlib import Path

import yaml

from .quantities import NUMBER, CaseError, field_text, shown

#: Deeper nesting than a case file needs (mapping > bodies > body > value) is refused before
#: PyYAML's recursive composer sees it.
MAX_DEPTH = 6
#: The largest case file read [bytes]: a case file is a few hundred bytes, a commented one a few
#: kB; anything larger is not one, and is refused before it is read.
MAX_BYTES = 1_000_000


PLAIN_INT = re.compile(r"[+-]?(?:0|[1-9][0-9]*)")
PLAIN_FLOAT = re.compile(NUMBER)


def _char(c) -> str:
    return f"U+{c if isinstance(c, int) else ord(c):04X}"


def join_field(parent: str, key) -> str:
    """'parent.key', the path of a field inside `parent` ('key' at the top level).

    Parameters
    ----------
    parent : str
        The parent's field path ('' at the top level).
    key : object
        The key.

    Returns
    -------
    str
    """
    return f"{parent}.{key}" if parent else str(key)


class _Frame:
    """A mapping or sequence being read: its field path and where in it the reader is."""

    def __init__(self, kind: str, path: str):
        self.kind, self.path = kind, path
        self.key = None  # mapping: the key whose value comes next (None: a key comes next)
        self.keys: dict[str, int] = {}  # mapping: key -> line
        self.index = 0  # sequence: index of the next item

    def child(self) -> str:
        if self.kind == "seq":
            return f"{self.path}[{self.index}]"
        return join_field(self.path, self.key) if self.key is not None else (self.path or "(top level)")

    def done(self, key: str | None = None):
        """A child node ended (`key`: it was a key)."""
        if self.kind == "seq":
            self.index += 1
        else:
            self.key = key


def scan_plain_yaml(text: str, path) -> None:
    """Walk the YAML events once and refuse what is not plain data, naming the field.

    Duplicated keys, keys that are not names, anchors and aliases, explicit tags, YAML 1.1
    spellings of numbers and booleans, nesting deeper than MAX_DEPTH, several documents.

    Parameters
    ----------
    text : str
        The file's text.
    path : str or pathlib.Path
        The file, named in messages.

    Returns
    -------
    None

    Raises
    ------
    CaseError
        Naming the file and the field.
    """
    try:  # the reader refuses control characters (NUL, ESC, ...) as it is made
        loader = yaml.SafeLoader(text)
    except yaml.reader.ReaderError as err:
        line = text[:err.position].count("\n") + 1
        raise CaseError(path, "(file)", f"not valid YAML: character {_char(err.character)} at line {line} is not "
                                        "allowed in a YAML file")
    stack: list[_Frame] = []
    documents = 0

    def here() -> str:
        return stack[-1].child() if stack else "(top level)"

    def refuse(problem: str, event) -> None:
        raise CaseError(path, here(), f"{problem} (line {event.start_mark.line + 1})")

    try:
        while loader.check_event():
            event = loader.get_event()
            if isinstance(event, yaml.DocumentStartEvent):
                documents += 1
                if documents > 1:
                    raise CaseError(path, "(file)",
                                    f"holds more than one YAML document (line {event.start_mark.line + 1})")
                continue
            if isinstance(event, (yaml.StreamStartEvent, yaml.StreamEndEvent, yaml.DocumentEndEvent)):
                continue
            if isinstance(event, (yaml.MappingEndEvent, yaml.SequenceEndEvent)):
                stack.pop()
                if stack:
                    stack[-1].done()
                continue
            if isinstance(event, yaml.AliasEvent) or event.anchor is not None:
                refuse("anchors (&name) and aliases (*name) are not allowed: write each value out", event)
            if event.tag is not None:
                refuse(f"explicit YAML tags ({event.tag}) are not allowed: a case file is plain data", event)
            is_key = bool(stack) and stack[-1].kind == "map" and stack[-1].key is None
            if is_key and not isinstance(event, yaml.ScalarEvent):
                refuse("a key must be a plain name, not a list or mapping", event)
            if isinstance(event, yaml.ScalarEvent):
                tag = loader.resolve(yaml.ScalarNode, event.value, event.implicit)
                raw = event.value
                if is_key:
                    if tag != "tag:yaml.org,2002:str":
                        refuse(f"a key must be a name, got {shown(raw)}"
                               + (" (a YAML merge key)" if tag.endswith(":merge") else ""), event)
                    frame = stack[-1]
                    if raw in frame.keys:
                        raise CaseError(path, join_field(frame.path, field_text(raw)),
                                        f"given twice (lines {frame.keys[raw]} and {event.start_mark.line + 1}); "
                                        "YAML would silently keep the last: give it once")
                    frame.keys[raw] = event.start_mark.line + 1
                    frame.done(field_text(raw))
                    continue
                if tag == "tag:yaml.org,2002:int" and not PLAIN_INT.fullmatch(raw) or \
                        tag == "tag:yaml.org,2002:float" and not PLAIN_FLOAT.fullmatch(raw):
                    refuse(f"{shown(raw)} is not a plain decimal number (YAML 1.1 reads underscores, leading zeros, "
                           "'a:b', .inf and .nan as numbers you may not mean): write e.g. 0.25", event)
                if tag == "tag:yaml.org,2002:bool" and raw not in ("true", "false"):
                    refuse(f"YAML 1.1 reads {shown(raw)} as a boolean: write true or false, or quote text", event)
                if stack:
                    stack[-1].done()
                continue
            # the start of a mapping or a sequence
            if len(stack) >= MAX_DEPTH:
                refuse(f"nested more than {MAX_DEPTH} levels deep; a case file needs 3", event)
            stack.append(_Frame("map" if isinstance(event, yaml.MappingStartEvent) else "seq",
                                here() if stack else ""))
    except yaml.reader.ReaderError as err:
        line = text[:err.position].count("\n") + 1
        raise CaseError(path, here(), f"not valid YAML: character {_char(err.character)} at line {line} is not "
                                      "allowed in a YAML file")
    except yaml.YAMLError as err:
        mark = getattr(err, "problem_mark", None)
        at = f" at line {mark.line + 1}, column {mark.column + 1}" if mark is not None else ""
        problem = getattr(err, "problem", None) or " ".join(str(err).split())
        raise CaseError(path, here() if stack else "(file)", f"not valid YAML{at}: {problem[:200]}")
    finally:
        loader.dispose()


#: What a file that is not a regular file is, by its mode, for messages.
_FILE_KINDS = ((stat.S_ISDIR, "a directory"), (stat.S_ISCHR, "a character device"), (stat.S_ISBLK, "a block device"),
               (stat.S_ISFIFO, "a named pipe (FIFO)"), (stat.S_ISSOCK, "a socket"))


def _kind(mode: int) -> str:
    return next((name for test, name in _FILE_KINDS if test(mode)), "not a regular file")


def read_small_file(path: Path, error=CaseError, max_bytes: int = MAX_BYTES,
                    what: str = "a case file is a few hundred") -> bytes:
    """The bytes of `path`, a regular file of at most `max_bytes` bytes, or `error(path, '(file)',
    problem)`.

    The kind and the size are checked before anything is read (``os.stat``, following symlinks):
    a device (/dev/zero, /dev/random), a FIFO, a socket or a directory is refused without being
    opened, a file larger than `max_bytes` without being read. The file is then opened without
    blocking (a FIFO swapped in meanwhile cannot hang the open), checked again on the open
    descriptor, and at most `max_bytes` + 1 bytes are read, so that a file that grows meanwhile is
    refused too, never read whole.

    Parameters
    ----------
    path : pathlib.Path
        The file.
    error : type
        The exception class raised, called as ``error(path, '(file)', problem)``.
    max_bytes : int
        The largest size accepted [bytes].
    what : str
        The end of the sentence "...; <what> bytes (limit N)" said of a file too large.

    Returns
    -------
    bytes
        The file's content.
    """
    try:
        st = os.stat(path)
    except ValueError:  # a NUL character in the path
        raise error(path, "(file)", "cannot read: the path holds a NUL character") from None
    except OSError as err:
        raise error(path, "(file)", f"cannot read: {err.strerror or err}") from None
    if not stat.S_ISREG(st.st_mode):
        raise error(path, "(file)", f"is {_kind(st.st_mode)}, not a regular file: only a file on disk is read "
                                    f"(at most {max_bytes} bytes)")
    if st.st_size > max_bytes:
        raise error(path, "(file)", f"is {st.st_size} bytes; {what} bytes (limit {max_bytes}, checked before reading)")
    try:
        fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0) | getattr(os, "O_CLOEXEC", 0))
    except OSError as err:
        raise error(path, "(file)", f"cannot read: {err.strerror or err}") from None
    with os.fdopen(fd, "rb") as fh:
        st = os.fstat(fh.fileno())
        if not stat.S_ISREG(st.st_mode):
            raise error(path, "(file)", f"is {_kind(st.st_mode)}, not a regular file (it changed while opened)")
        try:
            raw = fh.read(max_bytes + 1)
        except OSError as err:
            raise error(path, "(file)", f"cannot read: {err.strerror or err}") from None
    if len(raw) > max_bytes:
        raise error(path, "(file)", f"grew beyond {max_bytes} bytes while read; {what} bytes (limit {max_bytes})")
    return raw


def key_bytes(path, max_bytes: int = MAX_BYTES) -> bytes:
    """What a cache key takes from a case file.

    Its bytes, or, for a file `read_small_file` refuses (a device such as /dev/zero, a FIFO, a file
    too large, a missing one), the refusal itself, without reading it. Never raises; the loader
    refuses the file, naming it.

    Parameters
    ----------
    path : str or pathlib.Path
        The case file.
    max_bytes : int
        The largest size read [bytes].

    Returns
    -------
    bytes
    """
    try:
        return read_small_file(Path(path), CaseError, max_bytes)
    except CaseError as err:
        return b"\0refused\0" + err.problem.encode("utf-8", "replace")


def read_utf8(path: Path, error=CaseError, max_bytes: int = MAX_BYTES, what: str = "a case file is a few "
              "hundred") -> str:
    """The text of a small UTF-8 file, or `error(path, '(file)', problem)`.

    `read_small_file`: a regular file of at most `max_bytes`, checked before reading; refused when
    unreadable, not a regular file, larger than `max_bytes`, or not UTF-8 (the byte and its line
    named, not the text).

    Parameters
    ----------
    path : pathlib.Path
        The file.
    error : type
        The exception class raised, called as ``error(path, '(file)', problem)``.
    max_bytes : int
        The largest size accepted [bytes].
    what : str
        The end of the sentence "...; <what> bytes (limit N)" said of a file too large.

    Returns
    -------
    str
        The file's text (a UTF-8 byte-order mark dropped).
    """
    raw = read_small_file(Path(path), error, max_bytes, what)
    try:
        return raw.decode("utf-8-sig")
    except UnicodeDecodeError as err:
        line = raw[:err.start].count(b"\n") + 1
        raise error(path, "(file)", f"is not UTF-8 text (byte 0x{raw[err.start]:02x} at line {line}); "
                                    "save it as UTF-8")
