"""The calibration's files (results/calibration/): tables, plots, DEM runs and the report.

I/O at the edge: the numbers come from `calibration.case_calibration` and `calibration.fit`.
Text that comes from the user's files (the case's name, the measurement file's path and
provenance) is data: escaped where it enters Markdown (`as_text`) or a plot title (`as_title`), so
that it can neither add report lines nor markup nor break the plot.
"""

from __future__ import annotations

import html
import json
import math
import re
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.ticker  # noqa: E402
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pandas as pd  # noqa: E402

from contact_model import CRITERIA  # noqa: E402
from contact_model.case_file import Case  # noqa: E402
from contact_model.quantities import POISE  # noqa: E402
from records.files import save_figure  # noqa: E402

from .fit import WARN_CHI2_RED, Fit, exact_restitution  # noqa: E402
from .loop import LOOP_LAW  # noqa: E402


def as_text(text: str, limit: int = 200) -> str:
    """`text` from a user's file as one line of plain Markdown text: control characters and line
    breaks as spaces, HTML's <, > and & as entities, Markdown's code, link, image and table marks
    escaped (an underscore inside a word is literal Markdown: names keep theirs), cut to `limit`
    characters."""
    line = " ".join(re.sub(r"[\x00-\x1f\x7f-\x9f]", " ", str(text)).split())
    line = line if len(line) <= limit else line[:limit] + "..."
    return re.sub(r"([\\`*\[\]!|#])", r"\\\1", html.escape(line, quote=False))


def as_title(text: str) -> str:
    """`text` from a user's file in a matplotlib title: '$' escaped (no mathtext to parse), one line."""
    return " ".join(str(text).split())[:100].replace("$", r"\$")


def residual_table(case: Case, fits: dict[str, Fit]) -> pd.DataFrame:
    """One row per measurement: V, eps, sigma, and each fit's K, eps and residual."""
    m = case.measurements
    out = pd.DataFrame({"row": np.arange(1, len(m) + 1), "line": m.lines, "V": m.velocity, "eps": m.restitution,
                        "sigma": m.uncertainty if m.uncertainty is not None else np.nan})
    for name, f in fits.items():
        out[f"K_{name}"] = f.K
        out[f"eps_{name}"] = f.eps_fit
        out[f"residual_{name}"] = f.residuals
    return out


def engine_parameter_table(summary: dict) -> pd.DataFrame:
    rows = []
    for criterion in CRITERIA:
        for engine, params in summary["fits"][criterion]["engine_parameters"].items():
            for name, value in params.items():
                rows.append({"criterion": criterion, "engine": engine, "parameter": name, "value": value})
    return pd.DataFrame(rows)


def plot_fit(case: Case, fits: dict[str, Fit], path, loop: pd.DataFrame | None = None) -> None:
    """The data, the exact fits (x0, F0), the series fit, and the residuals below; with `loop`
    the DEM eps at the measured velocities."""
    m = case.measurements
    pair = case.pairs[0]
    V = np.geomspace(m.velocity.min() * 0.5, m.velocity.max() * 1.2, 200)
    fig, (ax, axr) = plt.subplots(2, 1, figsize=(7, 7), sharex=True, gridspec_kw={"height_ratios": [3, 1.3]})
    ax.errorbar(m.velocity, m.restitution, yerr=m.uncertainty, fmt="ko", ms=5, label="measured")
    styles = {"x0": ("tab:blue", "-"), "F0": ("tab:red", "-."), "series": ("tab:green", "--")}
    for name, f in fits.items():
        K = f.k * (V / f.V_ref) ** 0.2
        eps = exact_restitution(f.criterion)(np.minimum(K, 10)) if f.model == "exact" else \
            __import__("reference.restitution_closed_forms", fromlist=["paper_series"]).paper_series(K)
        color, ls = styles[name]
        label = f"exact fit, {name}" if f.model == "exact" else "paper's series fit (x0)"
        eta, eta_low, eta_high = f.viscosity(pair.E, pair.R, pair.M)
        ax.plot(V, eps, color=color, ls=ls,
                label=f"{label}: eta = {eta:.3g} Pa·s [{eta_low:.3g}, {eta_high:.3g}], K(V_max) = {f.k:.4f}")
        axr.plot(m.velocity, f.residuals, "o", color=color, mfc="none" if name != "x0" else color, label=name)
    if loop is not None and len(loop):
        for criterion, g in loop.groupby("criterion"):
            ax.plot(g.V, g.eps_dem, "x", color=styles[criterion][0], ms=9, mew=2,
                    label=f"{g.engine.iloc[0]} run with the {criterion} fit")
    ax.set_xscale("log")
    # Labels at 1, 2 and 5 of every decade: the data span about one decade, where the default
    # locator labels a single tick (10^0).
    axr.xaxis.set_major_locator(matplotlib.ticker.LogLocator(base=10, subs=(1.0, 2.0, 5.0)))
    axr.xaxis.set_major_formatter(matplotlib.ticker.FuncFormatter(lambda v, _: f"{v:g}"))
    axr.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())  # log minor labels overlap
    ax.set_ylabel("restitution coefficient eps")
    ax.set_title(f"{as_title(case.name)}: eps(V), fits of eta")
    ax.legend(fontsize=8, loc="lower left")  # the data fall from upper left to lower right
    axr.axhline(0, color="grey", lw=0.5)
    axr.set_xlabel("impact velocity V [m/s]")
    axr.set_ylabel("eps - fit")
    axr.legend(fontsize=7, ncol=3)
    save_figure(fig, path, dpi=110, bbox_inches="tight")
    plt.close(fig)


def write_fit(case: Case, summary: dict, fits: dict[str, Fit], out_dir) -> None:
    """fit.json, residuals.csv, engine_parameters.csv and fit.png in `out_dir`."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    (out / "fit.json").write_text(json.dumps(summary, indent=1) + "\n")
    residual_table(case, fits).to_csv(out / "residuals.csv", index=False, float_format="%.10g")
    engine_parameter_table(summary).to_csv(out / "engine_parameters.csv", index=False, float_format="%.10g")
    plot_fit(case, fits, out / "fit.png")


def loop_table(dumps, summary: dict, measured: pd.DataFrame | None = None) -> pd.DataFrame:
    """DEM eps at the measured velocities beside the fitted model's and the data (`measured`: the
    residual table, columns V and eps): `dumps` yields (path, metadata, columns, metrics) as
    `records.run_manifest.manifest_dumps` does."""
    criterion_of_law = {law: c for c, law in LOOP_LAW.items()}
    rows = []
    for path, meta, _, metrics in dumps:
        criterion = criterion_of_law[meta["law"]]
        eps_dem = metrics.eps_x0 if criterion == "x0" else metrics.eps_F0
        fit = summary["fits"][criterion]
        K = fit["K_at_V_ref"] * (meta["impact_velocity"] / fit["V_ref"]) ** 0.2
        eps_model = float(exact_restitution(criterion)([K])[0])
        row = {"criterion": criterion, "build": meta.get("build", meta["engine"]), "engine": meta["engine"],
               "V": meta["impact_velocity"], "K": K,
               "eps_dem": eps_dem, "eps_fit": eps_model, "dem_minus_fit": eps_dem - eps_model, "dump": Path(path).name}
        if measured is not None:
            at = measured[np.isclose(measured.V, row["V"], rtol=1e-12)]
            row["eps_measured"] = float(at.eps.mean())
        rows.append(row)
    return pd.DataFrame(rows).sort_values(["criterion", "V"]).reset_index(drop=True)


def _md(df: pd.DataFrame, fmt: str = ".4g") -> str:
    cols = list(df.columns)
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for _, r in df.iterrows():
        lines.append("| " + " | ".join(("" if np.isnan(v) else f"{v:{fmt}}") if isinstance(v, (float, np.floating))
                                       else str(v) for v in r) + " |")
    return "\n".join(lines)


def _own_unit(summary: dict, f: dict) -> str | None:
    """The case file's unit of viscosity where it is neither Pa·s nor P (then eta is given in it too)."""
    unit, ratio = summary.get("viscosity_unit"), f.get("eta_case_unit", 0) / f["eta_Pa_s"] if f["eta_Pa_s"] else 0
    if not unit or any(math.isclose(ratio, r, rel_tol=1e-12) for r in (1.0, 1 / POISE)):
        return None
    return unit


def answer_lines(summary: dict) -> list[str]:
    """The answer first: one line per criterion with eta in Pa·s and P (and in the unit the case
    file writes its viscosity in, where that is another), its 95 % interval, how the interval was
    made and chi²_red; then a warning where the stated uncertainties understate the scatter
    (chi²_red > WARN_CHI2_RED), and where the fitted constant loss is unphysical. Where the data
    contradict the model (``summary["warnings"]``: eps rises with V) each line says "do not use"
    instead of "use", and the warnings follow."""
    lines = []
    contradicted = bool(summary.get("warnings"))
    verb = "do not use" if contradicted else "use"
    case = as_text(summary["case"])
    for criterion in CRITERIA:
        f = summary["fits"][criterion]
        low, high = f["eta_interval_Pa_s"]
        unit = _own_unit(summary, f)
        own_eta = f"; {f['eta_case_unit']:.4g} {unit}" if unit else ""
        own_interval = (f"; {f['eta_interval_case_unit'][0]:.4g}–{f['eta_interval_case_unit'][1]:.4g} {unit}"
                        if unit else "")
        opened = [side for side, is_open in f["interval_open"].items() if is_open]
        basis = ("from the scatter: no uncertainties given" if not f["sigma_given"] else
                 "the stated uncertainties widened to the scatter (chi²_red > 1)" if f.get("widened") else
                 "from the stated uncertainties")
        eta = f["eta_Pa_s"]
        lines.append(f"- **{case}, {criterion}: {verb} eta = {eta:.4g} Pa·s ({eta / POISE:.4g} P{own_eta})**, "
                     f"95 % interval {low:.4g}–{high:.4g} Pa·s ({low / POISE:.4g}–{high / POISE:.4g} P{own_interval}; "
                     f"{basis}"
                     f"{'; open at the ' + ' and '.join(opened) + ' end' if opened else ''}), "
                     f"chi²_red = {f['chi2_red']:.3g}, {f['n']} points.")
        if f["sigma_given"] and f["chi2_red"] > WARN_CHI2_RED:
            lines.append(f"  - Warning: chi²_red = {f['chi2_red']:.3g} > {WARN_CHI2_RED:g}: the stated uncertainties "
                         f"understate the scatter about {math.sqrt(f['chi2_red']):.2g} times; an interval from them "
                         "alone would be too narrow, so it is the profile-t interval on the scale the scatter "
                         "estimates (`calibration/fit.py`).")
    xi = summary["constant_loss"]["xi_0"]
    if not 0 <= xi < 1:
        lines.append(f"  - Warning: the fitted velocity-independent loss xi_0 = {xi:.3g} is unphysical (a loss "
                     f"{'below 0 gives energy back' if xi < 0 else 'of 1 or more leaves no rebound'}): that extended "
                     "model does not describe these data; its test below says nothing about them.")
    lines += [f"  - Warning: {w}." for w in summary.get("warnings", [])]
    return lines


def case_section(summary: dict, residuals: pd.DataFrame, loop: pd.DataFrame | None, folder: str) -> list[str]:
    """The report's section of one calibrated case: its answer first (`answer_lines`), then how."""
    s, fx, ff, fs = summary, summary["fits"]["x0"], summary["fits"]["F0"], summary["fits"]["series"]
    sig = "given per row" if fx["sigma_given"] else f"not given; estimated from the scatter, sigma = {fx['sigma']:.2g}"
    lines = [f"## {as_text(s['case'])}", "", *answer_lines(s), "",
             f"Data: {as_text(s['measurements'])} ({fx['n']} points, "
             f"V = {s['velocity_range'][0]:g}–{s['velocity_range'][1]:g} m/s; "
             f"uncertainty {sig}). Provenance: "
             f"{as_text(s['provenance'].splitlines()[0]) if s['provenance'] else '(none given)'}",
             "",
             f"Bodies ({s['geometry']}): E* = {s['E_Pa']:.4g} Pa, R* = {s['R_m']:.6g} m, M* = {s['M_kg']:.6g} kg.", "",
             "| fit | K(V_max) [95 %] | V_D [m/s] [95 %] | eta [P] [95 %] | K range | chi²_red / rms residual "
             "| xi at V_max | V_c(1 %) [m/s] | V_c(5 %) [m/s] |",
             "|---|---|---|---|---|---|---|---|---|"]
    for name, f in (("exact, x0", fx), ("exact, F0", ff), ("paper's series (x0)", fs)):
        vc = f.get("V_c", {})
        lines.append(
            f"| {name} | {f['K_at_V_ref']:.4f} [{f['K_at_V_ref_interval'][0]:.4f}, {f['K_at_V_ref_interval'][1]:.4f}] "
            f"| {f['V_D']:.4g} [{f['V_D_interval'][0]:.4g}, {f['V_D_interval'][1]:.4g}] "
            f"| {f['eta_P']:.4g} [{f['eta_interval_P'][0]:.4g}, {f['eta_interval_P'][1]:.4g}] "
            f"| {f['K_range'][0]:.3f}–{f['K_range'][1]:.3f} | {f['chi2_red']:.3g} / {f['rms_residual']:.2g} "
            f"| {f['xi_at_V_max']:.3f} | {vc.get('0.01', float('nan')):.3g} | {vc.get('0.05', float('nan')):.3g} |")
    lines += ["",
              "V_c(beta) is the speed below which phi_1, phi_2 stay under beta (`reference.critical`). Under F0 it is "
              "tiny: T_F0 = T_x0 − (4/5) K δ_e/V + … has a term linear in K, so phi reaches beta at small K; the "
              "paper's V_c is the x0 one.", "",
              f"The paper's method (its second-order series) gives eta {100 * s['series_bias']:+.2f} % off the exact "
              "x0 fit "
              "on these data.", ""]
    cl, gf, tr, cv = s["constant_loss"], s["gugan_form"], s["residual_trend"], s["case_viscosity"]
    lines += ["**What the residuals say.** "
              f"The x0 residuals run from {residuals.residual_x0.iloc[0]:+.4f} "
              f"to {residuals.residual_x0.iloc[-1]:+.4f} "
              f"in file order; a line through them against ln V has slope {tr['b']:.4f} ± {tr['b_se']:.4f} "
              f"(t = {tr['t_statistic']:.1f}, 0 if the model's velocity dependence were the data's). "
              f"Adding a velocity-independent loss, eps² = (1 − xi_0) eps_x0(K)², gives xi_0 = {cl['xi_0']:.3f} ± "
              f"{cl['xi_0_se']:.3f} and cuts the rms residual from {fx['rms_residual']:.4f} "
              f"to {cl['rms_residual']:.4f} "
              f"(F = {cl['F']:.1f}, p = {cl['p_value']:.2g}). Gugan's own form 1 − e² = K0 + K1 U^0.4 fitted to the "
              f"same rows gives K0 = {gf['a']:.3f} ± {gf['a_se']:.3f}, "
              f"K1 = {gf['b']:.4f} ± {gf['b_se']:.4f} (s/m)^0.4. "
              "The viscoelastic model has no loss at vanishing speed (eps → 1 as V → 0).", ""]
    if cv["eta_P"] > 0:
        lines += [f"The case file's viscosity, {cv['eta_P']:.4g} P, would give eps = {min(cv['eps_x0']):.3f}–"
                  f"{max(cv['eps_x0']):.3f} (x0) at the measured velocities; the fitted eta is "
                  f"{cv['eta_ratio_fit_to_case']:.3f} times it.", ""]
    lines += ["eta when E* changes at fixed V_D (eta ∝ E*^{3/5}; the fit of eps(V) itself does not depend on E*):", "",
              _md(pd.DataFrame([{"criterion": c, "E* factor": r["factor"], "E* [Pa]": r["E_Pa"],
                                 "eta [P]": r["eta_Pa_s"] / POISE}
                                for c in CRITERIA for r in s["fits"][c]["modulus_sensitivity"]])), "",
              "Engine parameters of the calibrated contact (SI; `engine_parameters.csv`):", "",
              _md(engine_parameter_table(s)), ""]
    if loop is not None and len(loop):
        worst = loop.dem_minus_fit.abs().max()
        lines += [f"**Closing the loop.** The calibrated parameters run in {loop.build.iloc[0]} "
                  f"({loop.engine.iloc[0]}) at every measured "
                  f"velocity ({LOOP_LAW['x0']} law for x0, {LOOP_LAW['F0']} for F0): the DEM eps differs from the "
                  f"fitted model's by at most {worst:.2g}.", "", _md(loop.drop(columns=["dump"])), ""]
    lines += [f"![fit]({folder}/fit.png)", ""]
    return lines


def closed_forms_section(errors: pd.DataFrame, bias: pd.DataFrame) -> list[str]:
    """The report's table of the literature's closed forms against the solver."""
    wide = errors.pivot_table(index=["form", "criterion"], columns="K_max", values="max_abs_error").reset_index()
    wide.columns = [c if isinstance(c, str) else f"largest abs. error, K ≤ {c:g}" for c in wide.columns]
    b = bias.pivot_table(index=["form", "criterion"], columns="k_true", values="bias_noise_free").reset_index()
    b.columns = [c if isinstance(c, str) else f"eta bias, K(V_max) = {c:g}" for c in b.columns]
    return ["## The literature's closed forms for eps(K) against the reference solver", "",
            "Largest |eps_form − eps_ref| on [0, K_max], under the criterion each form assumes "
            "(`closed_forms.csv`, also the largest relative error there):", "", _md(wide, ".2e"), "",
            "Bias in the fitted eta (eta_fit / eta_true − 1) when a closed form replaces the exact model, on "
            "noise-free synthetic sets of 10 points over one decade in V (data from the solver under the form's "
            "criterion; `closed_form_bias.csv` also gives the median over noisy sets). Blank: the best K lies beyond "
            "the form's falling branch (the series turn up at K = 0.826), so it cannot fit.", "",
            _md(b, "+.2e"), ""]
