"""Dumps that cannot be corrupted silently: manifests with sha256 and relative paths, and every
way a dump can be unusable refused with the file named."""

import json
import shutil

import numpy as np
import pytest

from records.collision_metrics import ExtractionError, collision_metrics
from records.dump_file import DumpError, read_dump, write_dump
from records.files import file_sha256
from records.run_manifest import manifest_dumps, read_manifest, write_manifest
from test_collision_metrics import sampled_reference
from reference import solve_collision

META = {"engine": "test", "case": "x", "impact_velocity": 1.0, "K": 0.2}


@pytest.fixture
def job(tmp_path):
    """An engine job's folder: two dumps of the K = 0.2 reference collision and a manifest."""
    runs = tmp_path / "results" / "x" / "test" / "runs"
    runs.mkdir(parents=True)
    data = np.column_stack(sampled_reference(0.2))
    dumps = [runs / "a.csv", runs / "b.csv"]
    for d in dumps:
        write_dump(d, META, data)
    manifest = runs.parent / "manifest.json"
    write_manifest(manifest, dumps, [{"run": "c", "law": "default", "problem": "boom", "log": runs / "test.log"}],
                   case="x", engine="test", engine_seconds=0.5)
    return manifest


def test_manifest_holds_relative_paths_and_checksums(job):
    raw = json.loads(job.read_text())
    assert [d["path"] for d in raw["dumps"]] == ["runs/a.csv", "runs/b.csv"]
    assert raw["failed"] == [{"run": "c", "law": "default", "problem": "boom", "log": "runs/test.log"}]
    assert raw["dumps"][0]["sha256"] == file_sha256(job.parent / "runs" / "a.csv")
    got = list(manifest_dumps(job))
    assert len(got) == 2
    path, meta, cols, m = got[0]
    r = solve_collision(0.2)
    assert m.eps_x0 == pytest.approx(r["eps_x0"], rel=1e-4) and meta["K"] == 0.2


def test_a_moved_results_folder_reads_its_own_dumps(job, tmp_path):
    moved = tmp_path / "moved"
    shutil.move(tmp_path / "results", moved)
    manifest = moved / "x" / "test" / "manifest.json"
    assert read_manifest(manifest)["dumps"][1]["path"] == str(manifest.parent / "runs" / "b.csv")
    assert len(list(manifest_dumps(manifest))) == 2


def test_an_edited_dump_is_refused_naming_it(job):
    dump = job.parent / "runs" / "b.csv"
    text = dump.read_text()
    dump.write_text(text[:-3] + "9\n")  # the last digit of the last force
    with pytest.raises(DumpError, match=rf"^{dump}: the dump changed after the engine job wrote it"):
        list(manifest_dumps(job))


def test_a_dump_cut_at_a_line_boundary_is_refused_naming_it(job):
    dump = job.parent / "runs" / "a.csv"
    lines = dump.read_text().splitlines(keepends=True)
    dump.write_text("".join(lines[: len(lines) // 2]))
    with pytest.raises(DumpError, match=rf"^{dump}: the dump changed"):
        list(manifest_dumps(job))
    # Even with a manifest that agrees (rewritten by hand), an incomplete collision names the file.
    write_manifest(job, [dump], case="x", engine="test", engine_seconds=0.5)
    with pytest.raises(DumpError, match=rf"^{dump}: no complete collision in the dump: the contact is still open"):
        list(manifest_dumps(job))


def test_missing_dump_and_broken_manifest_are_refused_naming_them(job):
    (job.parent / "runs" / "a.csv").unlink()
    with pytest.raises(DumpError, match=r"a\.csv: cannot read dump"):
        list(manifest_dumps(job))
    job.write_text("{not json")
    with pytest.raises(DumpError, match=rf"^{job}: not a readable engine-job manifest"):
        read_manifest(job)


@pytest.mark.parametrize("spoil, said", [
    (lambda text: text.replace("# engine:", "# engine no colon", 1), "header line 2 is not 'key: <json>'"),
    (lambda text: text.replace("time,overlap,normal_velocity,normal_force", "t,x,v,f"), "expected the column line"),
    (lambda text: text.split("time,overlap")[0] + "time,overlap,normal_velocity,normal_force\n", "no data rows"),
    (lambda text: text.replace("\n0", "\nabc", 1), "unreadable data"),
])
def test_malformed_dump_text_is_refused_naming_the_file(tmp_path, spoil, said):
    good = tmp_path / "good.csv"
    write_dump(good, META, np.column_stack(sampled_reference(0.1)))
    bad = tmp_path / "bad.csv"
    bad.write_text(spoil(good.read_text()))
    with pytest.raises(DumpError, match=rf"^{bad}: {said}"):
        read_dump(bad)


def test_binary_dump_is_refused_naming_the_file(tmp_path):
    bad = tmp_path / "bin.csv"
    bad.write_bytes(b"# hertz-dem-dump: 1\n\xff\xfe\x00garbage")
    with pytest.raises(DumpError, match=rf"^{bad}: not a text file"):
        read_dump(bad)


def test_series_of_unequal_length_and_force_not_positive_on_contact():
    t = np.linspace(0, 1, 50)
    with pytest.raises(ExtractionError, match="equal-length"):
        collision_metrics(t, t - 0.1, np.ones(49), np.ones(50), 1.0)
    x = np.where((t > 0.1) & (t < 0.9), 0.1, -0.1)
    with pytest.raises(ExtractionError, match="not positive at the first sample in contact"):
        collision_metrics(t, x, np.ones(50), np.where(x > 0, 0.0, 0.0), 1.0)
