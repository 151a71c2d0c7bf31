"""A copy of the study's workflow in a temporary folder, for the tests that run Snakemake."""

import shutil
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def copy_workflow(dest: Path, case_text: str | None = None) -> Path:
    """Copy the Snakefile, the Makefile, config, workflow/, profiles/ and the engine decks into
    `dest`, with cases/steel.yaml (the project's, or `case_text`); link .venv-lammps, .venv-kratos and
    .yade-2025, where the default config's lammps-2025, kratos-10.4 and yade-2025 builds live (relative
    to the project), and the releases `make build` installed (.venv-lammps-<release>,
    .venv-kratos-<release>: the history's `make build` finds them there). Returns `dest`."""
    dest.mkdir(parents=True, exist_ok=True)
    for item in ("Snakefile", "Makefile", "config", "workflow", "profiles"):
        src = ROOT / item
        (shutil.copytree if src.is_dir() else shutil.copy)(src, dest / item)
    (dest / "cases").mkdir()
    shutil.copytree(ROOT / "cases" / "decks", dest / "cases" / "decks")
    shutil.copytree(ROOT / "cases" / "oblique", dest / "cases" / "oblique")  # config oblique: (extras `oblique`)
    if case_text is None:
        shutil.copy(ROOT / "cases" / "steel.yaml", dest / "cases")
    else:
        (dest / "cases" / "steel.yaml").write_text(case_text)
    releases = sorted(p.name for pattern in (".venv-lammps-*", ".venv-kratos-*") for p in ROOT.glob(pattern))
    for venv in (".venv-lammps", ".venv-kratos", ".yade-2025", *releases):
        if (ROOT / venv).exists():
            (dest / venv).symlink_to(ROOT / venv)
    return dest
