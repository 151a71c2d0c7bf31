"""YADE 2025's `en` + `vn` (the law en_vn: Brilliantov's force at the K of YADE's Pade) through the study,
at K = 0.1 and K = 1: its ladders, extrapolated with the x^{1/2} form's powers (contact_model.damping_forms),
meet its own equation to 1e-8 in eps, and every |error| lies within the resolution its ladder claims.

With the x^{1/4} powers the ladder gave every keyword law before, the same runs left eps errors of
2.6e-8 against a claimed resolution of 1e-8 (Codebase 2): the extrapolation's own bias."""

import subprocess
import sys
from pathlib import Path

import pandas as pd
import pytest

from contact_model.keywords import yade_en_vn_K
from engine_cases import missing
from reference import solve_collision
from workflow_copy import copy_workflow

pytestmark = pytest.mark.workflow
ROOT = Path(__file__).resolve().parents[1]


def test_en_vn_meets_its_own_equation_to_1e_8_at_k_0_1_and_1_within_its_resolution(tmp_path):
    if not (ROOT / ".yade-2025" / "yade").exists():
        missing("YADE 2025 is not installed; install it with: make yade-2025")
    # the restitutions whose en + vn K are 0.1 and 1 (YADE's Pade approximates Brilliantov's eps(K))
    told = [solve_collision(K)["eps_F0"] for K in (0.1, 1.0)]
    assert [yade_en_vn_K(e) for e in told] == pytest.approx([0.1, 1.0], rel=1e-3)
    case = ("name: steel\neffective_modulus: 109 GPa\nradius: 0.635 cm\ndensity: 7800 kg/m^3\n"
            "geometries: [sphere-sphere]\n"
            f"impact: {{restitution: [{told[0]:.12f}, {told[1]:.12f}], velocity: [1 m/s]}}\n")
    project = copy_workflow(tmp_path / "study", case)
    out = subprocess.run([sys.executable, "-m", "snakemake", "-j2", "steel", "--config",
                          "builds=[{id: yade-2025, code: yade, executable: .yade-2025/yade}]", "laws=[en_vn]",
                          "compare_builds=[]"], cwd=project, capture_output=True, text=True, timeout=900)
    assert out.returncode == 0, out.stderr[-3000:]
    table = pd.read_csv(project / "results" / "steel" / "summary.csv")
    limits = table[(table.dt == 0) & (table.law == "en_vn")].sort_values("K")
    assert len(limits) == 2 and list(limits.criterion) == ["F0", "F0"]
    assert limits.K.to_numpy() == pytest.approx([0.1, 1.0], rel=1e-3)
    for r in limits.itertuples():
        assert abs(r.err_eps) <= 1e-8, (r.K, r.err_eps)
        for q in ("T", "A", "eps"):
            error, resolution = getattr(r, f"err_{q}"), getattr(r, f"resolution_{q}")
            assert abs(error) <= resolution, (r.K, q, error, resolution)
            assert abs(error) + resolution <= 1e-6
    print("en_vn in yade-2025: " + "; ".join(
        f"K = {r.K:.3g}: eps {r.err_eps:+.1e} (resolution {r.resolution_eps:.1e}), T {r.err_T:+.1e} "
        f"({r.resolution_T:.1e}), A {r.err_A:+.1e} ({r.resolution_A:.1e})" for r in limits.itertuples()))
