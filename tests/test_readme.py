"""The README's user path, run exactly as written: its files (the fenced blocks whose first line
names one, `# cases/mine.yaml`) written into a copy of the project, then its commands, in order,
with bash, from that copy. A command the README shows that this test does not run is named in
ELSEWHERE with the place that runs it, so that no command of the README goes untried and
unnoticed.
"""

import re
from pathlib import Path

import pytest

import processes
from engine_cases import VERSIONS, require_default_builds
from workflow_copy import copy_workflow

ROOT = Path(__file__).resolve().parents[1]
README = (ROOT / "README.md").read_text()
BLOCKS = re.findall(r"^```(\w*)\n(.*?)^```$", README, flags=re.M | re.S)
#: The README's commands that this test does not run, and what runs them instead.
ELSEWHERE = {
    "make study": "the installs of `make test` (this suite) and `snakemake -j2 all` (CI's `make ci-study` on "
                  "the reduced study, tests/test_workflow.py's dry run of the full one)",
    "make test": ".ci/run",
    "make engines lammps-2025 kratos-10.4 slurm-venv": ".ci/run (`make slurm-up slurm-venv`, then `make test`)",
    "source .venv-slurm/bin/activate": "tests/test_slurm.py (it runs .venv-slurm/bin/snakemake)",
    "snakemake --profile profiles/slurm all": "tests/test_slurm.py and .ci/run (`make slurm-study`)",
}


def commands() -> list[str]:
    """Every command line of the README's sh blocks (comments and blank lines are not commands)."""
    lines = [line for kind, text in BLOCKS if kind == "sh" for line in text.splitlines()]
    return [line for line in lines if line.strip() and not line.lstrip().startswith("#")]


def files() -> dict[str, str]:
    """{path: text} of the README's blocks that start with '# <path>' (a path under cases/)."""
    out = {}
    for kind, text in BLOCKS:
        first = text.splitlines()[0] if text else ""
        m = re.match(r"# (cases/[\w./-]+?)(?::|$)", first)
        if kind in ("yaml", "csv") and m:
            out[m[1]] = text
    return out


def test_every_readme_command_is_run_here_or_elsewhere_by_name():
    assert set(ELSEWHERE) <= set(c.split("  #")[0].strip() for c in commands())
    ci = (ROOT / ".ci" / "run").read_text()
    assert "make test" in ci and "make slurm-up slurm-venv" in ci and "make slurm-study" in ci


def test_the_readme_user_path_runs_as_written(tmp_path):
    require_default_builds()
    project = copy_workflow(tmp_path / "project")
    (project / ".venv").symlink_to(ROOT / ".venv")
    for path, text in files().items():
        (project / path).write_text(text)
    assert {"cases/mine.yaml", "cases/mydata.csv", "cases/mydata.yaml"} <= set(files())
    run = [c for c in commands() if c.split("  #")[0].strip() not in ELSEWHERE]
    assert len(run) == 7, run  # eta for K, eta for a restitution, the time step, the case, your build, the
    # comparison, the calibration
    for command in run:
        out = processes.run(["bash", "-c", command], cwd=project, capture_output=True, text=True, timeout=900)
        assert out.returncode == 0, f"{command}\n{out.stdout[-3000:]}\n{out.stderr[-3000:]}"
        if "viscosity_for_k" in command:
            assert "mine (cases/mine.yaml): the viscosity eta giving each K" in out.stdout
        if "analysis.timestep" in command:
            assert "sphere-plane, law viscoelastic (criterion x0), V = 1 m/s" in out.stdout
            assert "error at your dt: min / median / max over the start phases" in out.stdout
        if "viscosity_for_restitution" in command:
            assert "mine (cases/mine.yaml): the viscosity eta whose viscoelastic collision restitutes" in out.stdout
    # What the README says each step leaves behind.
    assert (project / "results" / "mine" / "gate.txt").read_text().startswith("PASS: ")
    assert (project / "results" / "mine" / "report.html").exists()
    title = (project / "results" / "compare" / "mine" / "compare.md").read_text().splitlines()[0]
    assert title == (f"# Build comparison: lammps-2025 ({VERSIONS['lammps-2025']}, {project}/.venv-lammps/bin/lmp) → "
                     f"lammps-mine ({VERSIONS['lammps-2021']}, /usr/bin/lmp)"), title
    answers = (project / "results" / "calibration" / "report.md").read_text()
    assert "- **mydata, x0: use eta = " in answers and " Pa·s (" in answers


@pytest.mark.parametrize("path", ["docs/" + p.name for p in sorted((ROOT / "docs").glob("*.md"))])
def test_every_doc_is_linked_from_the_readme(path):
    assert f"]({path})" in README
