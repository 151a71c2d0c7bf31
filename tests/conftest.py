"""Every Snakemake the tests start imports this checkout's packages (engines/, postprocess/, ...),
also from the copied projects in tmp folders, which hold only the workflow: put the project first
on PYTHONPATH, ahead of whatever `pip install -e` the venv points at."""

import os
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
os.environ["PYTHONPATH"] = os.pathsep.join([str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])])
