"""The oblique impacts' report (results/oblique/<set>/report.md), its figures and verdict.json.

What a DEM user choosing a friction model reads first: which build's tangential model does what
its own equations say (the conformance matrix: build x tangential model x geometry), the three
figures of Chung & Ooi's test 4 (e_t, omega' and the rebound angle against incidence, every build
and model, with each model's reference and the rigid-body line of gross sliding), the gross-sliding
comparison with the rigid-body closed form, and every failed check with its figures.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pandas as pd

from records.files import save_figure, write_atomically

#: The figures: (quantity, axis label, file name).
FIGURES = (("e_t", "tangential restitution e_t = v_s'/v_s", "e_t.png"),
           ("omega_after", "rebound spin omega' [rad/s]", "omega_after.png"),
           ("rebound_angle", "rebound angle of the contact point [deg]", "rebound_angle.png"))


def verdict_of(checks: pd.DataFrame) -> dict:
    """PASS when every check passes (a declared known defect counts apart, never as a pass).

    Parameters
    ----------
    checks : DataFrame
        `analysis.oblique.oblique_checks`' rows (status PASS, FAIL or KNOWN DEFECT).
    """
    counts = checks.status.value_counts().to_dict() if len(checks) else {}
    failed = int(counts.get("FAIL", 0))
    judged = sum(int(counts.get(s, 0)) for s in ("PASS", "FAIL", "KNOWN DEFECT"))
    return {"verdict": "PASS" if judged and not failed else "FAIL", "checks": judged,
            "passed": int(counts.get("PASS", 0)), "failed": failed, "known_defects": int(counts.get("KNOWN DEFECT", 0)),
            "not_available": int(counts.get("NOT AVAILABLE", 0))}


def conformance_matrix(checks: pd.DataFrame) -> pd.DataFrame:
    """Build x (tangential model, geometry): 'PASS n/n', 'FAIL k of n' or 'KNOWN DEFECT k of n'.

    Parameters
    ----------
    checks : DataFrame
        `analysis.oblique.oblique_checks`' rows.
    """
    if not len(checks):
        return pd.DataFrame()

    def cell(g):
        if (g.status == "NOT AVAILABLE").all():
            return "n/a: " + "; ".join(sorted(set(g.detail)))[:120]
        g = g[g.status != "NOT AVAILABLE"]
        n, failed, known = len(g), int((g.status == "FAIL").sum()), int((g.status == "KNOWN DEFECT").sum())
        if failed:
            return f"FAIL {failed} of {n}"
        if known:
            return f"KNOWN DEFECT {known} of {n}"
        return f"PASS {n}/{n}"

    table = checks.groupby(["build", "model", "geometry"]).apply(cell, include_groups=False).rename("cell")
    return table.reset_index().pivot(index=["model", "geometry"], columns="build", values="cell").fillna("n/a")


def torque_note(model: str) -> str:
    """What the rigid-body table says beside a model whose force applies no torque (its form's
    ``lever_torque`` "none": ESyS's HertzMindlin): its w' stays w0, so (w' - rigid) is the declared
    defect's size, never a pass; '' for the others (and for a model the registry does not know)."""
    from contact_model.tangential_models import TANGENTIAL_MODELS

    entry = TANGENTIAL_MODELS.get(model)
    if entry is None or all(block.get("lever_torque") != "none" for block in entry.blocks.values()):
        return ""
    return "KNOWN DEFECT: the force applies no torque (w' = w0), contact_model/tangential_models.yaml"


def rigid_line(limits: pd.DataFrame, q: str) -> pd.Series:
    """The rigid-body gross-sliding value of `q` (e_t, omega_after or rebound_angle) at every limit
    row (`reference.rigid_body_sliding`, arms R, solid spheres, with the row's normal restitution):
    what Coulomb friction gives where the contact slides throughout (NaN where that sliding would
    reverse the slip, so that the contact cannot slide throughout).

    Parameters
    ----------
    limits : DataFrame
        Limit rows with normal_velocity, tangential_velocity, spin, friction, eps_ref, radius_1,
        geometry, and for two spheres radius_2 and the masses (mass_1, mass_2).
    q : str
        'e_t', 'omega_after' or 'rebound_angle'.
    """
    from reference import rigid_body_sliding

    out = []
    for r in limits.itertuples():
        R, m = r.radius_1, getattr(r, "mass_1", math.nan)
        plane = r.geometry == "sphere-plane"
        R2 = math.inf if plane else getattr(r, "radius_2", math.nan)
        m2 = math.inf if plane else getattr(r, "mass_2", math.nan)
        v_s = r.tangential_velocity + R * r.spin
        eps = r.eps_ref
        d = rigid_body_sliding(r.normal_velocity, eps, r.friction, R, m, 0.4 * m * R * R, v_s=v_s, R2=R2, m2=m2,
                               I2=math.inf if plane else 0.4 * m2 * R2 * R2)
        v_s_after = v_s + d["dv_s"]
        if v_s == 0 or v_s_after / v_s < 0:  # the slip would reverse: no gross sliding, no rigid value
            out.append(math.nan)
            continue
        value = {"omega_after": r.spin + d["dw1"], "e_t": v_s_after / v_s if v_s else math.nan,
                 "rebound_angle": math.degrees(math.atan2(v_s_after, eps * r.normal_velocity))}[q]
        out.append(value)
    return pd.Series(out, index=limits.index)


def draw_figures(limits: pd.DataFrame, folder) -> list[str]:
    """One figure per quantity of FIGURES against the incidence angle [deg], a panel per geometry:
    every build and model (markers: the engine at dt -> 0), each model's reference (line), the
    rigid-body gross-sliding line (dashed) and, on the plane of an elastic case, Mindlin–Deresiewicz
    partial slip (dotted, `analysis.oblique_theory.theory_for_rows`, computed once per case). Returns
    the files' names.

    Parameters
    ----------
    limits : DataFrame
        The ladders' limit rows (columns build, model, geometry, case, angle, spin, <q>, <q>_ref).
    folder : str or os.PathLike
        Where the PNG files go.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    names = []
    if not len(limits) or "angle" not in limits:
        return names
    plain = limits[(limits.spin == 0) & (limits.get("ranks", 1) == 1)] if "spin" in limits else limits
    geometries = [g for g in ("sphere-plane", "sphere-sphere") if (plain.geometry == g).any()]
    markers = "osD^vP*Xh<>"
    from analysis.oblique_theory import theory_for_rows

    theory = {}  # {case: the theory's curve or None}, for the three figures
    for case, rows in plain[plain.geometry == "sphere-plane"].groupby("case"):
        try:
            theory[case] = theory_for_rows(rows)
        except (ValueError, RuntimeError, KeyError, OSError):
            theory[case] = None  # a case file that no longer reads, or a theory that refuses: no curve
    for q, label, file_name in FIGURES:
        if q not in plain or not geometries:
            continue
        fig, axes = plt.subplots(1, len(geometries), figsize=(6.5 * len(geometries) + 3.5, 4.6), squeeze=False)
        for ax, geometry in zip(axes[0], geometries):
            g = plain[plain.geometry == geometry]
            for k, ((case, model), ref) in enumerate(g.groupby(["case", "model"])):
                ref = ref.drop_duplicates("angle").sort_values("angle")
                ax.plot(ref.angle, ref[f"{q}_ref"], "-", lw=0.9, alpha=0.7, color=f"C{k}", label=f"{model} reference")
            for k, ((build, model), e) in enumerate(g.groupby(["build", "model"])):
                e = e.sort_values("angle")
                ax.plot(e.angle, e[q], markers[k % len(markers)], ms=4, mfc="none", color=f"C{k}",
                        label=f"{build} {model}")
            try:
                first = g.drop_duplicates("angle").sort_values("angle")
                ax.plot(first.angle, rigid_line(first, q), "k--", lw=1.2,
                        label="rigid body, gross sliding" + (" (fixed normal)" if geometry == "sphere-sphere" else ""))
            except (AttributeError, KeyError, ValueError):
                pass  # rows without masses (an old summary): no rigid line
            for case in sorted(set(g.case)) if geometry == "sphere-plane" else ():
                md = theory.get(case)
                if md is not None:
                    ax.plot(md.angle, md[q], "k:", lw=1.6, label=f"Mindlin-Deresiewicz partial slip ({case})")
            ax.set_title(geometry)
            ax.set_xlabel("incidence from the normal [deg]")
            ax.set_ylabel(label)
            ax.grid(alpha=0.3)
        handles, labels = [], []
        for ax in axes[0]:
            for h, lab in zip(*ax.get_legend_handles_labels()):
                if lab not in labels:
                    handles.append(h)
                    labels.append(lab)
        fig.legend(handles, labels, loc="center right", fontsize=7, frameon=False)
        fig.tight_layout(rect=(0, 0, 1 - 3.3 / (6.5 * len(geometries) + 3.5), 1))
        save_figure(fig, folder / file_name, dpi=110)  # atomically: no half-written PNG
        plt.close(fig)
        names.append(file_name)
    return names


def _md_table(df: pd.DataFrame) -> str:
    if not len(df):
        return "(none)\n"
    head = "| " + " | ".join(str(c) for c in df.columns) + " |\n"
    rule = "|" + "---|" * len(df.columns) + "\n"
    return head + rule + "".join("| " + " | ".join(str(v) for v in row) + " |\n" for row in df.itertuples(index=False))


def junit_text(checks: pd.DataFrame) -> str:
    """The checks as JUnit XML (one testcase per check; FAIL a failure, KNOWN DEFECT skipped with
    its reason), for CI.

    Parameters
    ----------
    checks : DataFrame
        `analysis.oblique.oblique_checks`' rows.
    """
    import xml.etree.ElementTree as ET

    judged = checks[checks.status != "NOT AVAILABLE"] if len(checks) else checks
    suite = ET.Element("testsuite", name="hertz-dem-oblique", tests=str(len(judged)),
                       failures=str(int((checks.status == "FAIL").sum()) if len(checks) else 0),
                       skipped=str(int((checks.status == "KNOWN DEFECT").sum()) if len(checks) else 0))
    for r in checks[checks.status != "NOT AVAILABLE"].itertuples() if len(checks) else ():
        case = ET.SubElement(suite, "testcase", classname=f"{r.build}.{r.model}.{r.geometry}",
                             name=f"{r.case} angle {r.angle:.6g} spin {r.spin:g} np{r.ranks} {r.quantity}")
        if r.status == "FAIL":
            ET.SubElement(case, "failure", message=str(r.detail))
        elif r.status == "KNOWN DEFECT":
            ET.SubElement(case, "skipped", message=str(r.detail))
    return ET.tostring(suite, encoding="unicode") + "\n"


def write_oblique_report(summary: pd.DataFrame, limits: pd.DataFrame, checks: pd.DataFrame, report_path,
                         verdict_path, figures_folder, tolerance: float, junit_path=None) -> dict:
    """Write report.md, the figures and verdict.json; return the verdict.

    Parameters
    ----------
    summary : DataFrame
        Every rung and limit row (summary.csv).
    limits : DataFrame
        The ladders' limit rows.
    checks : DataFrame
        The gate's checks (`analysis.oblique.oblique_checks`).
    report_path, verdict_path, figures_folder : str or os.PathLike
        Where to write.
    tolerance : float
        The gate's tolerance [-], named in the report.
    junit_path : str or os.PathLike, optional
        Where to write the checks as JUnit XML.
    """
    verdict = verdict_of(checks)
    figures = draw_figures(limits, figures_folder)
    lines = ["# Oblique impacts: the tangential half of the contact", "",
             f"**Verdict: {verdict['verdict']}** ({verdict['passed']} of {verdict['checks']} checks pass, "
             f"{verdict['failed']} fail, {verdict['known_defects']} are declared known defects; tolerance "
             f"{tolerance:g} with the resolution added).", "",
             "Each build's tangential model is gated against its own equations (docs/tangential.md), the engine "
             "extrapolated to dt -> 0 over a ladder of time steps (analysis/oblique.py says how each error is "
             "formed).", "", "## Conformance matrix (build x tangential model x geometry)", ""]
    matrix = conformance_matrix(checks)
    lines.append(_md_table(matrix.reset_index()) if len(matrix) else "(no checks)\n")
    if len(limits) and "rigid_vt_after" in limits and limits.rigid_vt_after.notna().any():
        lines += ["## Gross sliding against the rigid-body closed form", "",
                  "Where the contact slides throughout, dv_t = -mu (1 + eps) v_n and, for a sphere on a plane with "
                  "lever arm R, dw = (5/2) mu (1 + eps) v_n / R. The difference is the engine's at dt -> 0; a "
                  "code whose arm is R - delta/2 departs from the second by the overlap's share. On the plane "
                  "only: between two spheres the line of centres turns during the contact, which the closed "
                  "form (a fixed normal) does not (about delta/R).", ""]
        g = limits.dropna(subset=["rigid_vt_after"])
        g = g[g.geometry == "sphere-plane"]
        V = np.hypot(g.normal_velocity, g.tangential_velocity)
        table = pd.DataFrame({"build": g.build, "model": g.model, "geometry": g.geometry,
                              "angle [deg]": g.angle.map(lambda a: f"{a:.4g}"),
                              "(vt' - rigid) / V": ((g.vt_after - g.rigid_vt_after) / V).map(lambda x: f"{x:.2e}"),
                              "(w' - rigid) R / V": ((g.omega_after - g.rigid_omega_after) * g.radius_1 / V).map(
                                  lambda x: f"{x:.2e}"),
                              "note": g.model.map(torque_note)})
        lines += [_md_table(table), ""]
    if figures:
        lines += ["## Against incidence (Chung & Ooi's test 4)", ""]
        lines += [f"![{f}](figures/{f})" for f in figures] + [""]
    failed = checks[~checks.status.isin(["PASS", "NOT AVAILABLE"])] if len(checks) else checks
    lines += ["## Checks that do not pass", ""]
    if len(failed):
        cols = ["build", "model", "geometry", "angle", "spin", "quantity", "status", "detail"]
        lines.append(_md_table(failed[cols]))
    else:
        lines.append("(none)\n")
    write_atomically(Path(report_path), "\n".join(lines) + "\n")
    write_atomically(Path(verdict_path), json.dumps(verdict, indent=2) + "\n")
    if junit_path is not None:
        write_atomically(Path(junit_path), junit_text(checks))
    return verdict

