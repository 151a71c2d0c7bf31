"""The benchmarks' own refusals (their figures are printed by `make bench`, never asserted)."""

import pytest
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.workflow  # runs the command as a user does: a process (tests/conftest.py)
def test_reference_solver_benchmark_refuses_an_unknown_baseline_naming_it():
    run = subprocess.run([sys.executable, "-m", "benchmarks.reference_solver", "--baseline", "no-such-rev"],
                         cwd=ROOT, capture_output=True, text=True, timeout=120)
    assert run.returncode != 0
    assert "--baseline no-such-rev: not a git revision" in run.stderr
    assert "Traceback" not in run.stderr


def test_sensitivity_benchmark_writes_the_model_lammps_runs_and_scales_one_parameter():
    """The deck words the sensitivity benchmark gives LAMMPS: the study's kn and eta_n0
    (engines.codes.CODES' contact parameters), one of them scaled by (1 + s)."""
    from benchmarks.sensitivity import ladders, model
    from engines.codes import CODES
    from engines.script_engine import number

    spec = ladders()[(0.1, "eta_n0")]
    p = CODES["lammps"].contact_parameters(spec.pair)
    assert model(spec, "kn", 0.0) == model(spec, "eta_n0", 0.0)
    assert f"hertz {number(p['kn'])} {number(p['eta_n0'] * (1 + 1e-5))} " in model(spec, "eta_n0", 1e-5)
    assert f"hertz {number(p['kn'] * (1 + 1e-5))} {number(p['eta_n0'])} " in model(spec, "kn", 1e-5)


def test_post_processing_benchmark_reads_a_rule_benchmark_file_and_refuses_a_case_with_no_engine_job(tmp_path):
    """benchmarks.post_processing: the last row of a Snakemake benchmark file, its numeric columns
    (s, cpu_time) as numbers and its h:m:s left out; a case whose engine jobs left no benchmark
    file is refused naming the folder and the command that makes them."""
    from benchmarks.post_processing import benchmark_row, engine_seconds

    tsv = tmp_path / "steel.tsv"
    tsv.write_text("s\th:m:s\tmax_rss\tcpu_time\n40.5\t0:00:40\t190.2\t12.25\n33.0\t0:00:33\t180.0\t9.5\n")
    assert benchmark_row(tsv) == {"s": 33.0, "max_rss": 180.0, "cpu_time": 9.5}
    with pytest.raises(SystemExit, match=r"logs/benchmarks/run_engine/no-such-case/: no engine job's benchmark "
                                         r"file; run `snakemake -j2 results/no-such-case/verdict.json` first"):
        engine_seconds("no-such-case")


def test_figure_margins_in_inches_place_the_axes_where_they_say():
    """records.files.set_margins: the grid's edges sit the given inches from the figure's edges
    (left 0.6 in of a 16 in wide figure is 0.0375 of it; top 0.7 in of 4.8 in), whatever its size."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from records.files import set_margins

    fig, axes = plt.subplots(1, 3, figsize=(16, 4.8))
    set_margins(fig, left=0.6, right=0.15, top=0.7, bottom=0.55, wspace=0.16)
    left, bottom = axes[0].get_position().x0 * 16, axes[0].get_position().y0 * 4.8
    right, top = (1 - axes[-1].get_position().x1) * 16, (1 - axes[-1].get_position().y1) * 4.8
    assert (left, right, top, bottom) == pytest.approx((0.6, 0.15, 0.7, 0.55), abs=1e-12)
    assert fig.subplotpars.wspace == 0.16
    plt.close(fig)
