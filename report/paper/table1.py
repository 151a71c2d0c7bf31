"""The paper's Table 1 recomputed: V_c(1 %) and V_c(5 %) for its five materials.

V_c(beta) = V_D (K_c(beta) / alpha)^5 with V_D = M*^2 E*^3 / (R* eta^5), for both geometries and
two critical-K rules: the reference solver's (the first K at which phi_1 or phi_2 reaches beta,
criterion x0) and the paper's K_c = 2.5 beta^{1/2}, i.e. V_c = 3.7 beta^{5/2} V_D. The masses
need densities, which the paper does not give: they come from the case files.
"""

from __future__ import annotations

from pathlib import Path

import pandas as pd

from contact_model import load_case
from reference import K_PREFACTOR
from reference.critical import PAPER_RULE_PREFACTOR, critical_dissipation

PAPER_TABLE_1 = Path(__file__).with_name("table1_paper.csv")
BETAS = (0.01, 0.05)


def paper_table_1() -> pd.DataFrame:
    return pd.read_csv(PAPER_TABLE_1, comment="#")


def recompute_table_1(cases_dir) -> pd.DataFrame:
    """One row per material x geometry x beta: V_D, the K_c of both rules, V_c of both rules
    [cm/s], the paper's V_c and the ratios computed / paper."""
    paper = paper_table_1()
    K_solver = {beta: critical_dissipation(beta, "x0") for beta in BETAS}
    rows = []
    for p in paper.itertuples():
        case = load_case(Path(cases_dir) / f"{p.case}.yaml")
        for pair in case.pairs:
            for beta, printed in zip(BETAS, (p.Vc1_cm_s, p.Vc5_cm_s)):
                K_rule = PAPER_RULE_PREFACTOR * beta**0.5
                v_solver = pair.velocity_for_dissipation(K_solver[beta]) * 100
                v_rule = pair.velocity_for_dissipation(K_rule) * 100
                rows.append({
                    "case": p.case, "geometry": pair.geometry, "beta": beta,
                    "density_kg_m3": pair.body_1.density, "V_D_cm_s": pair.viscous_velocity * 100,
                    "K_c_solver": K_solver[beta], "K_c_paper_rule": K_rule,
                    "Vc_solver_cm_s": v_solver, "Vc_paper_rule_cm_s": v_rule, "Vc_paper_cm_s": printed,
                    "ratio_solver_to_paper": v_solver / printed, "ratio_rule_to_paper": v_rule / printed,
                    # V_c ~ V_D ~ M*^2 ~ density^2: the density that would give the printed value.
                    "density_for_paper_value_rule": pair.body_1.density / (v_rule / printed) ** 0.5,
                })
    return pd.DataFrame(rows)


def rule_prefactor() -> float:
    """(2.5 / alpha)^5: the prefactor of V_c = (...) beta^{5/2} V_D that the paper's K rule implies."""
    return (PAPER_RULE_PREFACTOR / K_PREFACTOR) ** 5
