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


def test_changed_dumps_names_every_dump_that_is_not_the_one_its_job_wrote(job):
    """The check the gates run before a PASS, and the case summary's rerun trigger
    (workflow/rules/engines.smk): empty for intact dumps; a truncated dump, an edited one and a
    missing one each named."""
    from records.run_manifest import changed_dumps

    assert changed_dumps([job]) == []
    a, b = job.parent / "runs" / "a.csv", job.parent / "runs" / "b.csv"
    a.write_text(a.read_text()[: a.stat().st_size // 2])
    problems = changed_dumps([job])
    assert len(problems) == 1
    assert problems[0].startswith(f"{a}: the dump changed after the engine job wrote it (sha256 ")
    assert problems[0].endswith("rerun its engine job, e.g. snakemake --forcerun run_engine")
    b.unlink()
    assert [p.split(": ", 1)[1][:16] for p in changed_dumps([job])] == ["the dump changed", "cannot read dump"]
    assert changed_dumps([job.parent / "nowhere.json"])[0].startswith(
        f"{job.parent / 'nowhere.json'}: not a readable engine-job manifest")


FULL_DISK = """
import io, resource, signal, sys
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from records.files import save_figure
fig, ax = plt.subplots()
ax.imshow(np.random.default_rng(1).random((300, 300)))  # noise: a PNG of some 100 kB
size = len((fig.savefig(buf := io.BytesIO(), format="png", dpi=100), buf.getvalue())[1])
# The disk fills 100 bytes short of the picture: the last write, when the file is closed, fails
# (with EFBIG here, ENOSPC on a full disk).
signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
resource.setrlimit(resource.RLIMIT_FSIZE, (size - 100, resource.RLIM_INFINITY))
try:
    {save}
except OSError as err:
    print(f"{{type(err).__name__}}: {{err}}")
print(f"size {{size}}")
"""


@pytest.mark.workflow  # runs the command as a user does: a process (tests/conftest.py)
@pytest.mark.parametrize("atomic", [False, True])
def test_a_figure_whose_save_fails_leaves_no_file(tmp_path, atomic):
    """A disk that fills while a figure is saved (here: the process may write the picture's size
    less 100 bytes per file; a write past that fails, as on a full disk). Saved by matplotlib alone,
    a truncated PNG remains under the real name, its first bytes a PNG's; through
    records.files.save_figure, neither the figure nor a temporary file remains, and the error
    names the figure."""
    import re
    import subprocess
    import sys

    target = tmp_path / "timestep.png"
    save = "save_figure(fig, sys.argv[1], dpi=100)" if atomic else "fig.savefig(sys.argv[1], dpi=100)"
    out = subprocess.run([sys.executable, "-c", FULL_DISK.format(save=save), str(target)], capture_output=True,
                         text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    size = int(re.search(r"size (\d+)", out.stdout)[1])
    assert "File too large" in out.stdout and size > 50_000
    if atomic:
        assert f"[Errno 27] File too large: '{target}'" in out.stdout
        assert list(tmp_path.iterdir()) == []
    else:  # what the study saw: a truncated picture under its name
        assert target.stat().st_size == size - 100 and target.read_bytes().startswith(b"\x89PNG")


@pytest.mark.workflow  # runs the command as a user does: a process (tests/conftest.py)
def test_a_failed_atomic_write_leaves_the_old_file_and_no_temporary(tmp_path):
    """write_atomically of 10 kB where a process may write 4 kB per file (as on a full disk): the
    old file stays whole, no temporary file stays, and the error names the file."""
    import subprocess
    import sys

    from records.files import write_atomically

    target = tmp_path / "verdict.json"
    write_atomically(target, "old\n")
    script = ("import resource, signal, sys\nfrom records.files import write_atomically\n"
              "signal.signal(signal.SIGXFSZ, signal.SIG_IGN)\n"
              "resource.setrlimit(resource.RLIMIT_FSIZE, (4096, resource.RLIM_INFINITY))\n"
              "try:\n    write_atomically(sys.argv[1], 'x' * 10_000)\n"
              "except OSError as err:\n    print(err)\n")
    out = subprocess.run([sys.executable, "-c", script, str(target)], capture_output=True, text=True, timeout=60)
    assert out.stdout == f"[Errno 27] File too large: '{target}'\n", out.stderr
    assert target.read_text() == "old\n" and [p.name for p in tmp_path.iterdir()] == ["verdict.json"]


def test_every_figure_of_the_project_is_saved_through_save_figure():
    """No module calls matplotlib's savefig itself: each goes through records.files.save_figure."""
    import re
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]
    sources = [p for folder in ("reference", "contact_model", "records", "engines", "analysis", "verdict", "report",
                                "postprocess", "calibration", "workflow", "benchmarks")
               for p in (root / folder).rglob("*.py")]
    direct = [f"{p.relative_to(root)}:{i + 1}" for p in sources if p.name != "files.py" or p.parent.name != "records"
              for i, line in enumerate(p.read_text().splitlines()) if re.search(r"\.savefig\(", line)]
    assert direct == [] and len(sources) > 50


def test_the_cache_of_verified_dumps_does_not_hide_an_edit_that_keeps_size_and_mtime(job, tmp_path):
    """changed_dumps with its cache (what the case summary's rerun trigger uses): an intact dump is
    recorded and not hashed again; a dump edited in place to the same length with its mtime set back
    (os.utime, as `touch -r` does) is still named, its ctime having moved."""
    import os

    from records.run_manifest import changed_dumps

    cache = tmp_path / "cache" / "x.json"
    assert changed_dumps([job], verified=cache) == []
    records = json.loads(cache.read_text())
    b = job.parent / "runs" / "b.csv"
    assert sorted(records) == [str(job.parent / "runs" / "a.csv"), str(b)]
    assert records[str(b)][1] == b.stat().st_size and records[str(b)][4] == file_sha256(b)
    assert changed_dumps([job], verified=cache) == []
    before = b.stat()
    text = b.read_text()
    b.write_text(text[:-2] + ("9" if text[-2] != "9" else "8") + "\n")  # the last digit of the last force
    os.utime(b, ns=(before.st_atime_ns, before.st_mtime_ns))
    assert b.stat().st_size == before.st_size and b.stat().st_mtime_ns == before.st_mtime_ns
    problems = changed_dumps([job], verified=cache)
    assert len(problems) == 1 and problems[0].startswith(f"{b}: the dump changed after the engine job wrote it")
    assert str(b) not in json.loads(cache.read_text())  # named again on the next run
    assert changed_dumps([job], verified=cache) == problems
