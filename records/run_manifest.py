"""The manifest of an engine job: which dumps it wrote, their sha256, and which runs failed.

    {"case": "steel", "engine": "liggghts", "engine_seconds": 0.61,
     "dumps": [{"path": "runs/<run>.csv", "sha256": "…"}, …],
     "failed": [{"run": "<run>", "law": "viscoelastic", "problem": "…", "log": "runs/liggghts.log"}, …]}

Paths are relative to the manifest's own folder, so a copied or moved results folder reads its
own dumps, never the original's. Every dump is verified against its sha256 when it is read: a
dump edited, truncated or replaced after the run fails loudly, naming the file, instead of
flowing into the summary.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

from .collision_metrics import CollisionMetrics, ExtractionError, collision_metrics
from .dump_file import DumpError, parse_dump
from .files import file_sha256, write_atomically


def write_manifest(path, dumps, failed=(), **fields) -> dict:
    """Write the manifest `path` (atomically) listing `dumps` (absolute or relative paths, each
    hashed now) and `failed` (dicts with run, law, problem, log); `fields` go in as they are.

    Parameters
    ----------
    path : str or os.PathLike
        The manifest.json to write.
    dumps : iterable of str or os.PathLike
        The dumps the job wrote (absolute or relative paths), hashed now.
    failed : iterable of dict, optional
        The runs that failed: run, law, problem, log.
    **fields
        Further entries, written as they are (engine seconds, samples, ...).
    """
    path = Path(path)
    here = path.parent.resolve()

    def rel(p):
        return os.path.relpath(Path(p).resolve(), here)

    content = {**fields,
               "dumps": [{"path": rel(d), "sha256": file_sha256(d)} for d in dumps],
               "failed": [{**f, "log": rel(f["log"])} if f.get("log") else dict(f) for f in failed]}
    write_atomically(path, json.dumps(content, indent=1) + "\n")
    return content


def read_manifest(path) -> dict:
    """The manifest with every dump path made usable from here (joined to the manifest's folder).

    Parameters
    ----------
    path : str or os.PathLike
        The manifest.json.
    """
    path = Path(path)
    try:
        content = json.loads(path.read_text())
        for d in content["dumps"]:
            d["path"] = str(path.parent / d["path"])
        for f in content.get("failed", []):
            if f.get("log"):
                f["log"] = str(path.parent / f["log"])
    except (OSError, ValueError, KeyError, TypeError) as err:
        raise DumpError(f"{path}: not a readable engine-job manifest ({err})")
    return content


def dump_problem(path, sha256: str) -> str | None:
    """Why the dump `path` is not the one its engine job wrote (its sha256 differs from the
    manifest's `sha256`, or it cannot be read), naming the file; None when it is.

    'results/steel/lammps/runs/x.csv: the dump changed after the engine job wrote it (sha256
    3f2a…, manifest says 9c41…); rerun its engine job, e.g. snakemake --forcerun run_engine'.

    Parameters
    ----------
    path : str or os.PathLike
        The dump.
    sha256 : str
        The sha256 its engine job recorded in the manifest.
    """
    try:
        found = file_sha256(path)
    except OSError as err:
        return f"{path}: cannot read dump: {err.strerror}"
    return _changed(path, found, sha256)


def _changed(path, found: str, sha256: str) -> str | None:
    """`dump_problem`'s message for a dump whose bytes hash to `found` where the manifest says `sha256`."""
    if found != sha256:
        return (f"{path}: the dump changed after the engine job wrote it (sha256 {found[:12]}…, manifest "
                f"says {sha256[:12]}…); rerun its engine job, e.g. snakemake --forcerun run_engine")
    return None


def changed_dumps(manifest_paths, verified=None) -> list[str]:
    """`dump_problem` of every dump of the manifests `manifest_paths` that has one, in their order:
    empty when every dump is the one its engine job wrote. A manifest that cannot be read is a
    problem of its own.

    Every dump is hashed (sha256: about 1 s per GB once the files are cached, 3x that from disk)
    unless `verified` names a cache file (JSON), which records, for each dump found intact, its
    inode, size, mtime, ctime and the sha256 it was checked against: a dump whose stat still
    matches its record is not hashed again. Any change of a file's content, of its mtime (`touch
    -r` included), its mode or its name sets its ctime to now, which no user command sets back, so
    no changed dump passes for its record; a copied folder (new inodes) is hashed again once. With
    the cache the whole study's 5600 dumps (590 MB) take 0.1 s instead of 0.8 s (3.5 s from disk). A cache that
    cannot be read or written is left out (everything is hashed). The workflow's gates check
    every dump in full before a PASS; the case summary reruns when the cached list changes
    (workflow/rules/engines.smk).

    Parameters
    ----------
    manifest_paths : iterable of str or os.PathLike
        The manifests (engine jobs' manifest.json) whose dumps are checked.
    verified : str or os.PathLike, optional
        A cache file of the dumps verified before (inode, size, mtime, ctime, sha256); None
        hashes every dump.
    """
    cache = _read_cache(verified) if verified else {}
    problems = []
    for manifest in manifest_paths:
        try:
            dumps = read_manifest(manifest)["dumps"]
        except DumpError as err:
            problems.append(str(err))
            continue
        for d in dumps:
            key = os.path.abspath(d["path"])
            try:
                st = os.stat(key)
                stamp = [st.st_ino, st.st_size, st.st_mtime_ns, st.st_ctime_ns, d["sha256"]]
            except OSError:
                stamp = None
            if stamp is not None and cache.get(key) == stamp:
                continue
            problem = dump_problem(d["path"], d["sha256"])
            if problem:
                problems.append(problem)
                cache.pop(key, None)
            elif stamp is not None:
                cache[key] = stamp
    if verified:
        try:
            Path(verified).parent.mkdir(parents=True, exist_ok=True)
            write_atomically(verified, json.dumps(cache))
        except OSError:
            pass
    return problems


def _read_cache(path) -> dict:
    """The records of `changed_dumps`'s cache file `path`, or none where it cannot be read."""
    try:
        cache = json.loads(Path(path).read_text())
    except (OSError, ValueError):
        return {}
    return cache if isinstance(cache, dict) else {}


def verified_dump(path, sha256: str):
    """read_dump(path) after checking that the file is the one the run wrote (`dump_problem`).

    Parameters
    ----------
    path : str or os.PathLike
        The dump.
    sha256 : str
        The sha256 its engine job recorded in the manifest.
    """
    # One read for the hash and the parse: the bytes checked are the bytes read (and the file is
    # read once, not twice: a case has ~1000 dumps).
    try:
        content = Path(path).read_bytes()
    except OSError as err:
        raise DumpError(f"{path}: cannot read dump: {err.strerror}")
    problem = _changed(path, hashlib.sha256(content).hexdigest(), sha256)
    if problem:
        raise DumpError(problem)
    return parse_dump(content, path)


def measured_dump(path, sha256: str) -> tuple[dict, dict, CollisionMetrics]:
    """(metadata, columns, metrics) of a verified dump; any problem is a DumpError naming it.

    Parameters
    ----------
    path : str or os.PathLike
        The dump.
    sha256 : str
        The sha256 its engine job recorded in the manifest.
    """
    meta, cols = verified_dump(path, sha256)
    try:
        m = collision_metrics(cols["time"], cols["overlap"], cols["normal_velocity"], cols["normal_force"],
                              impact_velocity=meta["impact_velocity"])
    except (ExtractionError, KeyError) as err:
        raise DumpError(f"{path}: no complete collision in the dump: {err}")
    return meta, cols, m


def manifest_dumps(manifest_path):
    """Yield (path, metadata, columns, metrics) for every dump of a manifest, each verified.

    Parameters
    ----------
    manifest_path : str or os.PathLike
        An engine job's manifest.json.
    """
    for d in read_manifest(manifest_path)["dumps"]:
        yield (d["path"], *measured_dump(d["path"], d["sha256"]))
