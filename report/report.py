"""The comparison report: results/report.md (read by people and CI), report.html and the plots.

The verdict it shows is decided in `verdict.gate` (which also writes verdict.json and the
JUnit XML); the report only presents it, FAIL at the top with every failing check named.

Every law is gated against its own equation: the model's laws (viscoelastic, clipped, elastic) against
the viscoelastic model, each keyword law (`default`, each code's own restitution keyword, and the
other keywords) against the equation its code computes from what it is told. What a keyword
restitutes against the e it is told (its promise) and the paper's series are reported, not gated:
where they depart, that is a finding. The tangential half of the contact (tangential force,
friction, rotation, oblique impacts) is gated apart (report.oblique_report), and every report says
what that covers (`NOT_VALIDATED`).
"""

from __future__ import annotations

import html

import math
import re
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path

import numpy as np
import pandas as pd

from contact_model import CRITERIA, GATED_LAWS, LAWS, MODEL_LAWS
from contact_model.laws import KEYWORD_LAWS
from contact_model.keywords import KEYWORDS, promised_restitution
from engines.codes import CODES, integrators, keyword_of
from records.files import write_atomically
from reference import FIRST_ORDER, HERTZ_TAU

from records.quantities import readable
from analysis.report_references import report_references, report_rows
from verdict.gate import GATED_QUANTITIES, gating, with_build
from verdict.verdict_files import html_page

from .report_matrix import build_order, matrix_cells, matrix_html, matrix_markdown, md_text
from .report_plots import plot_errors, plot_ratios, start_drawing
from .report_resolution import ladder_settings, map_section, plot_ladders, resolution_sentence

#: Where the matrices go in the report's text (Markdown in report.md, HTML tables in report.html).
MATRIX = "@@gated-matrix@@"
#: What the study does not validate, said under every report's verdict (docs/verdict.md).
NOT_VALIDATED = ("**The tangential half** (tangential force, friction, rotation, oblique impacts) is not part of this "
                 "matrix: every run here is a head-on collision (the normal force alone). It is gated apart, "
                 "in LAMMPS's, YADE's and LIGGGHTS's tangential models only (the section \"Oblique impacts\" where "
                 "the study runs it, `snakemake -j2 oblique`, docs/tangential.md); ESyS and Kratos are not run "
                 "oblique yet, and a PASS here says nothing about their tangential force.")


def _md_table(df: pd.DataFrame, floatfmt: str = ".3g") -> str:
    cols = list(df.columns)
    lines = ["| " + " | ".join(cols) + " |", "|" + "---|" * len(cols)]
    for row in df.itertuples(index=False):
        # A '|' inside a cell (an engine's error message) would split the Markdown table.
        cells = [format(v, floatfmt) if isinstance(v, float) else str(v).replace("|", "\\|") for v in row]
        lines.append("| " + " | ".join(cells) + " |")
    return "\n".join(lines)


def _unquoted(tail: str) -> str:
    """A problem's quoted log lines ('    | line', engines.engine_process) as the log has them."""
    return "\n".join(re.sub(r"^ *\| ?", "", line) for line in tail.strip("\n").splitlines())


def _failed_runs_table(failed_runs) -> list[str]:
    """The runs an engine did not complete: one table row each, with the problem's first line,
    then each run's quoted engine-log lines (the problem's further lines) in a collapsed block,
    so that a log's lines never break the table. Markdown lines."""
    runs = with_build(pd.DataFrame(list(failed_runs)))
    heads, tails = zip(*(str(p).rstrip("\n").partition("\n")[::2] for p in runs.problem))
    lines = [_md_table(runs.assign(problem=list(heads))[["case", "build", "law", "run", "problem", "log"]]), ""]
    for run, log, tail in zip(runs.run, runs.log, tails):
        if tail.strip():
            lines += [f"<details><summary>{html.escape(str(run))}: the last lines of its engine log "
                      f"(<code>{html.escape(str(log))}</code>)</summary>", "",
                      f"<pre>{html.escape(_unquoted(tail))}</pre>", "", "</details>", ""]
    return lines


def findings(table: pd.DataFrame, series_cmp: pd.DataFrame, ladder_runs: pd.DataFrame | None = None) -> list[str]:
    """Short statements computed from the results (numbers, not adjectives). `table` holds the
    gated laws' ladder limits (dt = 0) and the other laws' runs; `ladder_runs` the gated rungs."""
    out = []
    gated = table[table.law.isin(GATED_LAWS)]
    if len(gated):
        e = np.abs(gated[[f"err_{q}" for q in GATED_QUANTITIES]].to_numpy())
        out.append(f"Extrapolated to dt -> 0, the gated ladders ({len(gated)} ladder x criterion limits) agree with "
                   f"the reference solver to a median relative error of {np.median(e):.1e} and at most {e.max():.1e} "
                   "in T, A and eps.")
        both = gated[gated.law == "viscoelastic"]
        if both.build.nunique() >= 2:
            piv = both.pivot_table(index=["case", "geometry", "criterion", "K"], columns="build", values="err_eps")
            piv = piv.dropna()
            if len(piv):
                gap = float((piv.max(axis=1) - piv.min(axis=1)).max())
                out.append(f"The engines ({', '.join(piv.columns)}) agree with each other in eps to {gap:.1e} at "
                           "dt -> 0 in every case, geometry and K.")
    if ladder_runs is not None and len(ladder_runs) and ladder_runs.build.nunique() >= 2:
        raw = ladder_runs[ladder_runs.law == "viscoelastic_clipped"]
        if raw.build.nunique() >= 2:
            piv = raw.pivot_table(index=["case", "geometry", "criterion", "K", "time_step_factor"], columns="build",
                                  values="err_T").dropna()
            if len(piv):
                gap = float((piv.max(axis=1) - piv.min(axis=1)).max())
                worst = float(piv.abs().max().max())
                out.append(f"At each time step the builds' raw errors are one and the same ({', '.join(piv.columns)}, "
                           f"clipped law: T errors up to {worst:.1e}, differing between builds by at most {gap:.1e}): "
                           f"{integrators(raw.engine)} are one "
                           "discrete map on positions and half-step velocities, which damps with the velocity half a "
                           "step old and is first-order in dt.")
    out += [_keyword_finding(build, group) for (build, _), group in
            table[table.law.isin(KEYWORD_LAWS) & (table.dt == 0)].groupby(["build", "law"], sort=False)]
    x0 = table[(table.criterion == "x0") & table.law.isin(MODEL_LAWS)]
    if len(x0):
        i = x0.K.idxmax()
        r = x0.loc[i]
        out.append(f"The paper's truncated series depart from the reference solver by "
                   f"{r.series_err_T:+.1e} (T), {r.series_err_A:+.1e} (A), {r.series_err_eps:+.1e} (eps), "
                   f"{r.series_err_Q1:+.1e} (Q1), {r.series_err_Q2:+.1e} (Q2) at K = {r.K:.3g} (criterion x0).")
    if series_cmp is not None:
        bad = series_cmp.dropna(subset=["paper"])
        bad = bad[np.abs(bad.difference) > bad.rounding]
        for r in bad.itertuples():
            out.append(f"Paper's eq. {r.equation}: the K^{r.order} coefficient of {r.quantity} is printed as "
                       f"{r.paper:g}; the reference solver gives {r.computed:.4f}.")
    f0 = table[(table.criterion == "F0") & table.law.isin(MODEL_LAWS)]
    if len(f0):
        r = f0.loc[f0.K.idxmax()]
        x0_slope = FIRST_ORDER["T/T_e"]
        out.append(f"Under criterion F0 (separation at zero force) T/T_e = {r.T_ref / r.T_e:.4f} at K = {r.K:.3g}, "
                   f"below the x0 value: the paper's T series (+{x0_slope:.4f} K) is the x0 one; under F0 the linear "
                   f"coefficient is {x0_slope:.4f} - 0.8/tau_e = {x0_slope - 0.8 / HERTZ_TAU:.4f}.")
    return out


@dataclass
class ReportInputs:
    """What the report shows, as the study's rules read it.

    table: summary.csv; checks, verdict: from `verdict.gate` (the report shows them, as a
    matrix, `report.report_matrix`, and links to checks.csv, which the caller writes next to
    it; it decides nothing); series_cmp: the paper's series coefficients against the solver's;
    timing: the engine jobs' count and seconds; not_run: velocities the plan left out, with the
    reason; failed_runs: runs the engine did not complete (of every law: gated ones also fail
    their checks); convergence, convergence_orders, convergence_spread: results/convergence/;
    regressions: the LAMMPS regression cases; claims, table1, energy_check: results/paper/;
    calibration: the text of results/calibration/report.md, included as a section; reference: the
    reference table over a K grid (results/reference/collisions.csv) for the curves of the plots;
    builds: the build ids in config order (the matrix's rows and the plots' styles);
    not_available: the plans' ``not_available`` cells (build, engine, law, geometry, reason);
    code_notes: {code: notes} (`engines.codes.EngineCode.notes`) of the builds' codes, printed
    under the matrix; ladder: config `ladder` (the time steps of the gated runs, described);
    title: the report's heading; folder: where the report and its summary.csv and checks.csv
    are (results, or results/<case> for a case's own report); case_reports: each case's own
    report ({case, verdict, checked, failed, report: its path from here}); comparisons: each
    build comparison ({pair, report, regression, fix, unchanged, new, removed}).
    """

    table: pd.DataFrame
    checks: pd.DataFrame
    verdict: dict
    series_cmp: pd.DataFrame | None = None
    timing: dict | None = None
    not_run: list = field(default_factory=list)
    failed_runs: list = field(default_factory=list)
    convergence: pd.DataFrame | None = None
    convergence_orders: pd.DataFrame | None = None
    convergence_spread: pd.DataFrame | None = None
    #: The largest dt / T_R for each tolerance over K and e (analysis.timestep_maps.largest_steps).
    largest_steps: pd.DataFrame | None = None
    #: A case report's time-step section (report.report_timestep.case_error_maps), Markdown lines.
    timestep: list = field(default_factory=list)
    regressions: pd.DataFrame | None = None
    claims: pd.DataFrame | None = None
    table1: pd.DataFrame | None = None
    energy_check: pd.DataFrame | None = None
    calibration: str | None = None
    #: The text of results/oblique/reduced/report.md (the oblique impacts' reduced set), a section.
    oblique: str | None = None
    reference: pd.DataFrame | None = None
    builds: list | None = None
    not_available: list = field(default_factory=list)
    code_notes: dict | None = None
    ladder: dict | None = None
    title: str = "Viscoelastic Hertz contact in DEM engines: comparison report"
    folder: str = "results"
    #: The plans' notes (`engines.plan.Plan.notes`): what runs and what does not, in words.
    plan_notes: list = field(default_factory=list)
    #: Build folders beside the report that this run's builds do not own (`stale_build_folders`): left
    #: by an earlier run with another build list, said to be stale under the verdict, never listed.
    stale_folders: list = field(default_factory=list)
    case_reports: list = field(default_factory=list)
    comparisons: list = field(default_factory=list)
    #: The reference values the report shows (`analysis.report_references.report_references` of
    #: table and reference: the plots' reference curve, the model's eps beside the keywords); the
    #: workflow's scripts compute them, the report solves nothing. None: computed from table.
    references: dict | None = None


def _keyword_section(limits: pd.DataFrame, builds, model_restitution: dict) -> list[str]:
    """The engines' restitution keywords: each against its own equation (gated: the law `default`
    of the matrix above), what it promises, and the viscoelastic model's eps beside it
    (`model_restitution`, {(K, criterion): eps}: `analysis.report_references`)."""
    rows = []
    for r in limits.itertuples():
        keyword = KEYWORDS[keyword_of(r.law, r.engine)]
        told = float(r.matched_restitution)
        own = promised_restitution(keyword.name, told)
        model = model_restitution[(float(r.K), r.criterion)]
        rows.append({"case": r.case, "build": r.build, "geometry": r.geometry, "keyword": f"`{keyword.name}`",
                     "criterion": r.criterion, "K": r.K, "told e": told, "eps, its equation": own,
                     "promise error": own - told, "eps, engine (dt -> 0)": own * (1 + r.err_eps),
                     "engine vs its equation": r.err_eps, "eps, viscoelastic model": model})
    table = pd.DataFrame(rows)
    order = build_order(builds, table)
    table = table.iloc[np.lexsort((table.K.to_numpy(), [order.index(b) for b in table.build]))]
    keywords = [KEYWORDS[keyword_of(law, e)] for law, e in dict.fromkeys(zip(limits.law, limits.engine))]
    defects = {k.name: k.known_defect for k in keywords if k.known_defect}
    forms = dict.fromkeys(k.damping_form for k in keywords)
    equations = " or ".join(f"{f.equation()} ({', '.join(k.name for k in keywords if k.damping_form is f)})"
                            for f in forms)
    return ["## The engines' restitution keywords: their own equation, their promise", "",
            "What a user runs: each code's own damping keyword told a restitution coefficient e "
            "(docs/keywords.md). Each is gated against the equation its code computes, "
            f"{equations}, with the coefficient from e by the code's own map (the law `default` of "
            "the matrix, and the keyword laws beside it: ladders extrapolated to dt -> 0 against that equation's "
            "closed form); what that equation restitutes against e is the keyword's promise, reported, not gated. "
            "The keywords are told the viscoelastic model's eps at one K (config default_law_match_K) under the "
            "criterion the keyword's force allows, or a case's own `restitution:`; the last column is the model's "
            "eps at the run's own K, the physics the keyword stands in for.", "",
            _md_table(table, ".6g"), "",
            *[f"- Known defect of `{name}`: {text}." for name, text in defects.items()], ""]


#: The quantities of the physical-results table, in the order a reader of Chung & Ooi expects.
PHYSICAL = ("T", "delta_max", "F_max", "A", "eps")
#: Hertz's contact time t_c = C (M*^2 / (R* E*^2 V))^{1/5}: C = tau_e (15/16)^{2/5} = 2.8683...
HERTZ_CONSTANT = HERTZ_TAU * (15.0 / 16.0) ** 0.4


def _physical_section(limits: pd.DataFrame, builds=None) -> list[str]:
    """The case's physical results: per geometry, a row per law, criterion and velocity with the
    reference's T, delta_max, F_max, A and eps in readable units, each with the engines' (dt -> 0)
    largest relative difference from it over the row's builds; the elastic rows beside Hertz's
    closed forms.

    A model law's equation is the same in every build: one row for all of them. A keyword law
    (`default` and the other keywords) runs in each build the equation of that build's keyword,
    told the same e: one row per keyword (naming its builds), with that equation's reference (its
    T, delta_max, F_max, A and eps at what it was told, summary.csv's ``*_ref``), what was asked
    and that the gate checks the keyword against its own equation. Builds whose references differ
    never share a row."""
    if not len(limits) or "delta_max_ref" not in limits.columns:
        return []
    lines = ["## Physical results", "",
             "Each row is the reference solution of the equation its builds run, in physical units, and beside "
             "each value the largest relative difference of those builds' ladder limits (dt -> 0) from it: T the "
             "contact time, delta_max the largest overlap, F_max the largest normal force, A = pi R* delta_max, eps "
             "the restitution (under the criterion of the row). The viscoelastic laws and the elastic one are one "
             "equation in every build: one row. A keyword law (`default`: each code's own restitution keyword, and "
             "the other keywords) runs in each build its keyword's own equation, told e: a row per keyword, with that "
             "equation's T, delta_max, F_max, A and eps at what it was told; the engines are gated against that "
             "equation, not against e (what the equation restitutes against e is the keyword's promise: "
             "docs/keywords.md). The coefficient is the viscoelastic K of the row, or the b (c, K) of the keyword's "
             "own equation.", ""]
    order = build_order(builds, limits)
    everyone = [b for b in order if b in set(limits.build.astype(str))]
    for geometry, g in limits.groupby("geometry", sort=False):
        keyword = [keyword_of(law, engine) if law in LAWS else None for law, engine in zip(g.law, g.engine)]
        told = g.matched_restitution if "matched_restitution" in g.columns else pd.Series(math.nan, index=g.index)
        # A row: one law, criterion, velocity and K; a keyword law's also one keyword and told e; and never
        # two references (T, delta_max, F_max, A and eps of the reference, to 9 digits).
        refs = [tuple(f"{float(v):.9g}" for v in r) for r in g[[f"{q}_ref" for q in PHYSICAL]].to_numpy()]
        keys = pd.Series(list(zip(g.law, [k or "" for k in keyword], g.criterion, g.V, g.K,
                                  [f"{t:.12g}" if pd.notna(t) else "" for t in told], refs)), index=g.index)
        rows = []
        for key, s in g.groupby(keys, sort=False):
            law, name, criterion, V, K, _, _ = key
            r = s.iloc[0]
            members = [b for b in order if b in set(s.build.astype(str))]
            every = len(everyone) > 1 and members == everyone
            row = {"law": law + (f" `{name}`" if name else ""),
                   "builds": f"all {len(everyone)}" if every else ", ".join(members),
                   "criterion": criterion, "V [m/s]": f"{V:.6g}",
                   "coefficient": _coefficient(name, _told_of(r)[0] if name else math.nan, K,
                                               direct=bool(name) and _told_of(r)[1])}
            for q in PHYSICAL:
                worst = s[f"err_{q}"].abs().max() if f"err_{q}" in s else float("nan")
                row[q] = readable(q, float(r[f"{q}_ref"])) + (f" (±{worst:.0e})" if pd.notna(worst) else "")
            row["asked"] = _asked(name, _told_of(r)[0], float(r.eps_ref), direct=_told_of(r)[1]) if name else "-"
            sort = (LAWS.index(law) if law in LAWS else len(LAWS), min(order.index(b) for b in members),
                    CRITERIA.index(criterion) if criterion in CRITERIA else len(CRITERIA), V, K)
            rows.append((sort, row))
        table = pd.DataFrame([row for _, row in sorted(rows, key=lambda item: item[0])])
        if not any(keyword):  # no keyword law: nothing was asked but the case's viscosity
            table = table.drop(columns="asked")
        lines += [f"### {geometry}", "", _md_table(table), ""]
        elastic = g[g.law == "elastic"]
        if len(elastic):
            r = elastic.iloc[0]
            lines += [md_text(f"Hertz's closed forms at V = {r.V:.6g} m/s: t_c = C (M*^2 / (R* E*^2 V))^(1/5) with "
                              f"C = tau_e (15/16)^(2/5) = {HERTZ_CONSTANT:.10f} gives {readable('T', r.T_e)}; "
                              "delta_max = (15 M* V^2 / (16 E* sqrt(R*)))^(2/5) = "
                              f"{readable('delta_max', r.A_e / (r.A_ref / r.delta_max_ref))}, F_max = (4/3) E* "
                              "sqrt(R*) delta_max^(3/2) (= (5/4) M* V^2 / delta_max) and eps = 1: the elastic row's "
                              "reference."), ""]
    return lines


def _told_of(row) -> tuple[float, bool]:
    """(what a keyword's summary row was told, whether that is its code's own input): the restitution
    e it was asked for, or its own input given directly (`told_input`: yade:betan's beta, the
    conformance kit's --beta); (nan, False) for neither."""
    direct = row.get("told_input") if hasattr(row, "get") else getattr(row, "told_input", None)
    if direct is not None and pd.notna(direct):
        return float(direct), True
    e = row.get("matched_restitution") if hasattr(row, "get") else getattr(row, "matched_restitution", None)
    return (float(e), False) if e is not None and pd.notna(e) else (math.nan, False)


def _coefficient(keyword: str, told: float, K: float, direct: bool = False) -> str:
    """The coefficient of a physical-results row's equation: the viscoelastic K of a model law's
    row, the b (c; K of a Brilliantov keyword) a keyword's code computes from what it was told
    (`direct`: told its own input, not a restitution)."""
    if not keyword:
        return f"K = {K:.4g}"
    k = KEYWORDS[keyword]
    return f"{k.damping_form.symbol} = {k.b(told if direct else k.told_for(told)):.4g}"


def _asked(keyword: str, told: float, eps: float, direct: bool = False) -> str:
    """What a keyword's row was asked for, and that the gate checks its own equation: the e it was
    told (as a damping ratio or a dashpot's eta_n where the code takes that), and how far its
    equation's eps is from e (its promise); `direct`: its own input, given as it stands (no promise)."""
    k = KEYWORDS[keyword]
    if direct:
        return f"{k.told} = {told:.6g}, given as it stands (no restitution asked); gated against its own equation"
    how = {"beta": f" as betan = {k.told_for(told):.6g} (Thornton's beta of e)",
           "eta": " as the eta_n restituting it at this V (x0)"}.get(k.told, "")
    promise = "" if k.told == "eta" else f"; its equation's eps - e = {eps - told:+.2e}"
    return f"e = {told:.6g}{how}; gated against its own equation{promise}"


def _keyword_finding(build: str, limits: pd.DataFrame) -> str:
    """What a build's restitution keyword did: its own equation at dt -> 0 (the gate), what that
    equation restitutes when told e (its promise; contact_model.keywords), and its known defect."""
    engine = limits.engine.iloc[0]
    keyword = KEYWORDS[keyword_of(limits.law.iloc[0], engine)]
    worst = float(limits[[f"err_{q}" for q in GATED_QUANTITIES]].abs().max().max())
    told, direct = _told_of(limits.iloc[0])
    if direct:  # told its own input (the conformance kit's --beta): no restitution asked, no promise
        form = keyword.damping_form
        return (f"{build}'s {keyword.written} computes its own equation, {form.equation()} ({form.symbol} = "
                f"{keyword.b(told):.6g} told {keyword.told} = {told:.6g} as it stands"
                f"{', the force clipped' if keyword.clipped else ''}), to {worst:.1e} at dt -> 0.")
    told = float(limits.matched_restitution.dropna().iloc[0]) if limits.matched_restitution.notna().any() else math.nan
    own = promised_restitution(keyword.name, told) if math.isfinite(told) else math.nan
    if keyword.form == "velocity":  # a dashpot told the eta_n of e by the study: no promise of its own
        c = keyword.b(keyword.told_for(told))
        return (f"{build}'s {keyword.written} computes its own equation, x'' + c x' + (5/4) x^(3/2) = 0 (c = {c:.6g}, "
                f"the eta_n the study computes to restitute e = {told:.4f} at each run's velocity), to {worst:.1e} at "
                "dt -> 0; at a fixed eta_n its c falls as V^(-1/5), so its restitution rises with the velocity.")
    form = keyword.damping_form
    text = (f"{build}'s {keyword.written} computes its own equation, {form.equation()} "
            f"({form.symbol} = {keyword.b(keyword.told_for(told)):.6g} told e = {told:.4f}"
            f"{', the force clipped' if keyword.clipped else ''}), to "
            f"{worst:.1e} at dt -> 0; that equation restitutes {own:.6f} ({keyword.criterion}): its promise is off "
            f"by {own - told:+.2e}.")
    return text + (f" Known upstream: {keyword.known_defect}." if keyword.known_defect else "")


def stale_build_folders(folder: Path, builds) -> list[str]:
    """The build folders in `folder` (each with the manifest.json of an engine job) whose build is
    not among `builds`: an earlier run's with another build list, by path."""
    folder = Path(folder)
    if not folder.is_dir():
        return []
    return sorted(str(p) for p in folder.iterdir()
                  if p.is_dir() and (p / "manifest.json").is_file() and p.name not in set(builds))


def write_report(inputs: ReportInputs, out_dir: Path, workers: int = 1, plots: bool = True) -> None:
    """Write report.md, report.html and the plots of `inputs` into out_dir (the plots in
    `workers` processes, `report.report_plots.start_drawing`; `plots` False: left undrawn, the
    reports as they are, their image links dangling, where matplotlib's seconds are not wanted).

    Every law is gated: its results are shown by its ladders' limits (summary rows with dt = 0),
    its rungs in the ladders' and the map's figures.
    """
    i = inputs
    table, checks, verdict, builds, not_available = i.table, i.checks, i.verdict, i.builds, i.not_available
    series_cmp, timing, not_run, failed_runs, ladder = i.series_cmp, i.timing, i.not_run, i.failed_runs, i.ladder
    convergence, convergence_orders, convergence_spread = i.convergence, i.convergence_orders, i.convergence_spread
    regressions, claims, table1, energy_check = i.regressions, i.claims, i.table1, i.energy_check
    calibration, reference, code_notes = i.calibration, i.reference, i.code_notes
    references = i.references if i.references is not None else report_references(table, reference)
    full, table, limits, ladder_runs = report_rows(table)
    out_dir = Path(out_dir)
    # Not named `plots`: that is the flag, and a Path there (always true) drew the figures of --no-plots too.
    plot_dir = out_dir / "plots"
    plot_dir.mkdir(parents=True, exist_ok=True)
    tolerance = verdict["tolerance"]
    has_rows = len(table) > 0
    curve = references["curve"]
    figures = []
    if has_rows:  # the slowest first: with two workers it is drawn beside the three others
        figures += [(plot_errors, (table, tolerance, plot_dir / "errors.png", builds)),
                    (plot_ratios, (table, "x0", plot_dir / "ratios_x0.png", curve, builds)),
                    (plot_ratios, (table, "F0", plot_dir / "ratios_F0.png", curve, builds))]
    if len(limits) and len(ladder_runs):
        figures.append((plot_ladders, (ladder_runs, limits, tolerance, plot_dir / "ladders.png", builds)))
    figures_drawn = start_drawing(figures if plots else [], workers)
    cells = matrix_cells(gating(checks), not_available, builds)  # the known-defect checks have their own section
    # What the study supplies of a law in each build's release, marked at the cells.
    # A code of the conformance kit alone (engines.codes.KIT_CODES) has no engine of the study: nothing supplied.
    supplied = ({b: CODES[e].supplied_in(v) if e in CODES else {} for (b, e), v in
                 table.groupby(["build", "engine"], sort=False).engine_version.first().items()} if has_rows else {})
    html_blocks = {MATRIX: (matrix_markdown(cells, tolerance, code_notes, supplied), matrix_html(cells, supplied))}

    lines = [
        f"# {inputs.title}", "",
        f"**Verdict: {verdict['verdict']}** — {verdict['checked'] - verdict['failed']} of {verdict['checked']} gated "
        "checks (engine build x law x geometry x criterion x quantity) pass; tolerances (relative, engine vs "
        "reference): "
        + ", ".join(f"{q} {tolerance[q]:g}" for q in GATED_QUANTITIES) + ".", "",
        *(f"**Warning**: {w}.\n" for w in verdict.get("warnings", [])),  # a tolerance above 1e-2
    ]
    sentence = resolution_sentence(gating(checks), tolerance)
    if sentence:
        lines += [sentence, ""]
    if verdict["verdict"] != "PASS":
        lines += ["Failing checks:", ""] + [f"- {f}" for f in verdict["failures"]] + [""]
    lines += [NOT_VALIDATED, ""]
    if inputs.stale_folders:
        lines += [f"**Stale folders**: {', '.join(f'`{f}`' for f in inputs.stale_folders)} beside this report are "
                  "from an earlier run with another build list. This report was made by this run's builds alone "
                  f"({', '.join(inputs.builds)}); it neither uses nor lists those folders' runs, and the verdict "
                  "they were part of is withdrawn. Rerun that run's own command to make them current.", ""]
    lines += [f"Generated {datetime.now(timezone.utc):%Y-%m-%d %H:%M UTC} from `{inputs.folder}/summary.csv` "
              f"({len(full) - len(limits)} rows of engine runs, one per run and end-of-collision criterion, and "
              f"{len(limits)} of ladder limits, dt = 0; sha256 {verdict['summary_sha256'][:12]}…) and "
              f"`{inputs.folder}/checks.csv`. Machine-readable: `verdict.json`, `junit.xml` (one test case per "
              "check).", ""]
    lines += _parts_section(inputs.case_reports, inputs.comparisons, calibration is not None)
    if inputs.folder != "results":  # a case's report opens with its collisions in physical units
        lines += _physical_section(limits, builds) + list(inputs.timestep)
    if has_rows:
        versions = table.groupby(["build", "engine"], sort=False).engine_version.unique()
        lines += ["## Engines", "", "Every engine build (config `builds:`) runs the same cases, laws, geometries and "
                  "time steps; its version is read from the engine and recorded in every dump.", ""]
        lines += [f"- **{b}** ({e}): {', '.join(v)}" for (b, e), v in versions.items()] + [""]
        if inputs.folder == "results":  # the study's report: each case's rows beside it
            lines += ["Cases: " + ", ".join(f"[{c}]({c}/summary.csv)" for c in sorted(table.case.unique())), ""]
    lines += ["## Gated checks: the worst relative error of each cell, engine vs reference solver", "",
              "Rows: engine builds; columns: contact law, geometry, end-of-collision criterion. Laws: viscoelastic "
              "with the attractive tail kept (criteria x0 and F0 from one trajectory), viscoelastic clipped at zero "
              "force (F0 only), elastic (eta = 0: Hertz alone), default (the engine's own restitution keyword, "
              "against its own equation: see its section below), and other keywords as laws of their own ("
              f"{', '.join(law for law in KEYWORD_LAWS if law != 'default')}: contact_model/laws.py). A cell fails "
              "when any of its checks (T, A, eps) exceeds its tolerance once its resolution is added, or when one of "
              "its runs failed or left no result. Hover a cell of report.html for the worst quantity, case, K and "
              "run, and the reason of a failure.", "", ladder_settings(ladder), "", MATRIX, ""]
    if has_rows:
        lines += ["## Against K", "", ("Every engine build a marker and colour of its own (hollow; a dot at the "
                                       "centre: sphere-plane), smaller along the build list, so that builds that "
                                       "agree show as nested markers; the reference solver as a line, the paper's "
                                       "series dashed."),
                  "", "![criterion x0](plots/ratios_x0.png)", "", "![criterion F0](plots/ratios_F0.png)", "",
                  "The errors of the gated laws extrapolated to dt -> 0, each with its resolution (grey bar):", "",
                  "![errors](plots/errors.png)", ""]
        if len(limits) and len(ladder_runs):
            lines += ["Every gated ladder, rung by rung: the part of each rung's error that the extrapolation "
                      "removes (`rungs_T`, `rungs_A`, `rungs_eps` of the ladder's limit row in summary.csv).", "",
                      "![ladders](plots/ladders.png)", ""]
    lines += map_section(ladder_runs, builds)
    # The promise is of a keyword asked for a restitution: one told its own input (yade:betan's beta, the
    # conformance kit's --beta) was asked none.
    asked_e = (table.law.isin(KEYWORD_LAWS) & table.matched_restitution.notna()
               if has_rows and "matched_restitution" in table.columns else None)
    if asked_e is not None and asked_e.any():
        lines += _keyword_section(table[asked_e], builds, references["model_restitution"])
    if series_cmp is not None:
        pub = series_cmp.dropna(subset=["paper"])
        lines += ["## The paper's series coefficients against the reference solver's (criterion x0)", "",
                  _md_table(pub[["quantity", "order", "equation", "paper", "computed", "difference"]], ".5g"), ""]
    if i.plan_notes:
        lines += ["## What the plans say", "", *(f"- {note}" for note in i.plan_notes), ""]
    if len(not_run) or len(failed_runs):
        lines += ["## Runs not made or not completed", ""]
        if len(not_run):
            lines += ["Not run (see `results/<case>/plan.json`):", "",
                      _md_table(pd.DataFrame(list(not_run))[["case", "geometry", "K", "V", "delta_e/R*",
                                                             "reason"]]), ""]
        if len(failed_runs):
            lines += ["Runs the engine did not complete (each fails its law's checks above):", "",
                      *_failed_runs_table(failed_runs)]
    if convergence is not None:
        lines += _convergence_section(convergence, convergence_orders, convergence_spread)
    if i.largest_steps is not None and len(i.largest_steps):
        lines += _largest_steps_section(i.largest_steps)
    if regressions is not None:
        lines += _lammps_regression_section(regressions, checks)
    if claims is not None:
        lines += _paper_section(claims, table1, energy_check)
    if calibration is not None:
        lines += _included_report_section(calibration)
    if i.oblique is not None:
        lines += _included_report_section(i.oblique, folder="oblique/reduced")
    if has_rows:
        lines += ["## Findings", ""] + [f"- {f}" for f in findings(table, series_cmp, ladder_runs)] + [""]
    if timing:
        lines += ["## Timing", "", _md_table(pd.DataFrame([timing])), ""]
    text = "\n".join(lines)
    # report.html links the other reports' HTML pages (report.md their Markdown)
    markdown_text, html_text = text, re.sub(r"\]\(([\w.-]+)/report\.md\)", r"](\1/report.html)", text)
    for placeholder, (md, block) in html_blocks.items():
        markdown_text = markdown_text.replace(placeholder, "\n".join(md).rstrip())
        # Raw HTML passes through Python-Markdown as a block; the Markdown around it (legend, notes) is kept.
        md_rest = [line for line in md if not line.startswith("|")]
        html_text = html_text.replace(placeholder, f"\n{block}\n\n" + "\n".join(md_rest).strip())
    write_atomically(out_dir / "report.md", markdown_text)
    _write_html(html_text, out_dir / "report.html")
    figures_drawn()


def _lammps_regression_section(regressions: pd.DataFrame, checks: pd.DataFrame) -> list[str]:
    """The LAMMPS regression cases (engines.lammps.regression_cases): build x case -> the largest
    relative error of the run written as a user would (and whether its checks pass), then every run."""
    user = regressions[regressions.role == "user"]
    cells = pd.DataFrame(index=pd.Index(user.build.unique(), name="build"))
    for (build, case), sel in user.groupby(["build", "case"], sort=False):
        worst = float(sel[["err_T", "err_A", "err_eps"]].abs().max(axis=1).max())
        mine = checks[(checks.build == build) & (checks.law == f"regression:{case}")]
        ok = len(mine) > 0 and bool(mine["pass"].all())
        cells.loc[build, case] = f"{worst:.3g} ({'right' if ok else 'defect'})"
    cells = cells.reset_index()
    wall = user[user.case == "wall-modulus"]
    nu_err = float(wall.defect_err_T.iloc[0]) if len(wall) else float("nan")
    mixing_measured = "; ".join(
        f"{r.build}: T off by {r.err_T:+.3g}, eps by {r.err_eps:+.3g}" if pd.notna(r.err_T) else
        f"{r.build}: no result ({r.problem if isinstance(r.problem, str) and r.problem else 'its run failed'})"
        for r in user[user.case == "mixing"].itertuples()) or "no run"
    return ["## LAMMPS: regression cases of two 2021 defects", "",
            "Run in every LAMMPS build; reported, not gated (their checks are in `checks.csv` with `gates` False, "
            "and `compare` shows a fixed defect as a fix). Each case is written twice: the way a user would write "
            "it, and the way the study writes the contact (the control, which must match the reference).", "",
            "- **wall-modulus**: an elastic sphere on a plane of its own material (nu = 0.3) with `fix wall/gran "
            "... hertz/material E 0 nu`. Debian's build (29 Sep 2021) takes E/(2(1-nu)) for the wall instead of "
            f"E/(2(1-nu^2)), (1+nu) times too stiff: T off by (1+nu)^(-2/5) - 1 = {nu_err:.4%}. The study gives "
            "the wall an explicit `hertz` kn.",
            "- **mixing**: two equal spheres (K = 0.1) of two atom types, one `pair_coeff i i` line per type, the "
            "1-2 pair left to mixing. In the 2021 build the mixed pair loses its Hertz and damping models (its "
            "coefficients are left uninitialised: the contact time comes out wrong, or the run ends in SIGSEGV). "
            f"In this study: {mixing_measured}. The study writes one `pair_coeff * *` line.", "",
            "Worst |relative error| of T, A and eps, build x case (right: every check within its tolerance):", "",
            _md_table(cells), "", "Every run (`results/lammps/regressions.csv`):", "",
            _md_table(regressions[["build", "engine_version", "case", "role", "written as", "err_T", "err_A",
                                   "err_eps"]], ".4g"), ""]


def _parts_section(case_reports: list, comparisons: list, calibration: bool) -> list[str]:
    """Links to the study's other reports, each with its verdict: every case's own report, every
    build comparison (its counts of regressions and fixes), the calibration (a section below)."""
    if not (case_reports or comparisons or calibration):
        return []
    lines = ["## Every report of the study", ""]
    if case_reports:
        lines += ["Each case on its own (`snakemake -j2 <case>` gates on it): " + "; ".join(
            f"[{r['case']}]({r['report']}) {r['verdict']} ({r['checked'] - r['failed']} of {r['checked']} checks)"
            for r in case_reports) + ".", ""]
    for c in comparisons:
        baseline, candidate = c["pair"].split("_vs_", 1)
        lines += [f"Build comparison [{baseline} → {candidate}]({c['report']}): {c['regression']} regressions, "
                  f"{c['fix']} fixes, {c['unchanged']} unchanged (a report, not a gate).", ""]
    if calibration:
        lines += ["Calibration of eta from measured restitution: [its report](calibration/report.md), and the "
                  "section \"Calibrating eta\" below.", ""]
    return lines


def _included_report_section(markdown_text: str, folder: str = "calibration") -> list[str]:
    """A report included as a section (results/calibration/report.md, results/oblique/reduced/report.md)
    one heading level down, its relative links pointing into `folder` (relative to this report)."""
    text = re.sub(r"^(#+) ", r"#\1 ", markdown_text, flags=re.M)
    text = re.sub(r"\]\((?!https?:|/|#)([^)]+)\)", rf"]({folder}/\1)", text)
    return text.rstrip().splitlines() + [""]


def _convergence_section(largest: pd.DataFrame, orders: pd.DataFrame | None = None,
                         spread: pd.DataFrame | None = None) -> list[str]:
    """Which time step a user may take: the largest dt per build x law x criterion that keeps T,
    A and eps within each threshold (`analysis.convergence.largest_dt_table`), the observed
    orders, and how far the builds differ."""
    def dt_text(r):
        if r.how == "none":
            return "none (finer than the sweep)"
        prefix = ">= " if r.how == "coarsest" else ""
        suffix = " (below the sweep)" if r.how == "beyond" else ""
        return f"{prefix}T_e/{r.T_e_over_dt:.3g} = {r.dt_over_T_R:.2g} T_R{suffix}"

    # One row per law, criterion and K where every build gives the same dt (to 1 %), else per build.
    rows = []
    for (law, criterion, K), g in largest.groupby(["law", "criterion", "K"], sort=True):
        same = all(gt.how.nunique() == 1 and not (gt.dt_over_T_e.max() - gt.dt_over_T_e.min()
                                                   > 0.01 * gt.dt_over_T_e.abs().max())
                   for _, gt in g.groupby("threshold"))
        for build, gb in ([(f"all {g.build.nunique()}", g[g.build == g.build.iloc[0]])] if same
                          else g.groupby("build", sort=False)):
            rows.append({"law": law, "criterion": criterion, "K": K, "builds": build,
                         **{f"within {r.threshold:g}": dt_text(r) for r in gb.sort_values("threshold",
                                                                                      ascending=False).itertuples()}})
    table = pd.DataFrame(rows)
    lines = ["## Which time step? Convergence from production steps on", "",
             "Steel, V = 1 m/s, eta set per K, both geometries, every viscoelastic law a build can express, "
             "dt = T_e/10 ... T_e/2000. For each law, criterion and K: the largest dt that keeps T, A and eps within "
             "each threshold in both geometries, in Hertz times T_e and in Rayleigh times T_R of the sphere "
             "(interpolated between the sweep's steps in log|error| against log dt, or carried below its finest "
             "step with the slope of its last two; per build in "
             "`results/convergence/largest_dt.csv`, the points in `errors.csv`). 'all N' where every build gives "
             "the same dt to 1 %. Production DEM runs take dt = 0.1 to 0.4 T_R.", "", _md_table(table), ""]
    if orders is not None and len(orders):
        finite = orders.dropna(subset=["order"])
        o = finite.groupby(["law", "quantity"]).order.agg(["min", "max"]).reset_index()
        lines += ["Observed order over dt <= T_e/250 (`orders.csv`): "
                  + "; ".join(f"{r.law} {r.quantity} {r.min:.2f}-{r.max:.2f}" for r in o.itertuples()) + ".", ""]
    if spread is not None and len(spread):
        worst = spread.loc[spread.spread.idxmax()]
        lines += [f"The builds differ little: at the same law, geometry, K, criterion and step their errors differ "
                  f"by at most {spread.spread.max():.1e} of the error's size ({worst.law}, {worst.geometry}, "
                  f"K = {worst.K:g}, "
                  f"{worst.quantity}, dt = T_e/{1 / worst.h:.0f}; `build_spread.csv`). {integrators(CODES)} "
                  "are one map on positions and half-step velocities, so a time step safe in one build is safe in "
                  "all.", ""]
    return lines + ["![convergence](plots/convergence.png)", "",
                    "The gated runs' own ladders (T_e/125 ... T_e/2000 x sqrt(K)), rung by rung, and what their "
                    "extrapolation removes from each: ![ladders](plots/ladders.png)", ""]


def _largest_steps_section(table: pd.DataFrame) -> list[str]:
    """The advisor's summary: the largest dt / T_R holding 1e-2, 1e-3 and 1e-4 at every start phase."""
    wide = table.pivot_table(index=["law", "K", "e"], columns="tolerance", values="dt_max_over_T_R",
                             dropna=False).dropna(how="all").reset_index()
    wide.columns = [c if isinstance(c, str) else f"dt/T_R for {c:g}" for c in wide.columns]
    return ["## Which time step? At every phase of the contact's start", "",
            "From the engines' discrete map (every build follows it to 1e-12 at 0.05-0.3 T_R: docs/timestep.md): the "
            "largest dt / T_R that keeps T, A and eps within each tolerance whatever phase of a step the contact "
            "starts at, for the viscoelastic law over K (steel spheres) and for each code's restitution keyword "
            "over the e it is told (codes whose keywords compute one equation share a row; 0.6: the grid's top). "
            "Your case, law and step: `python -m postprocess.timestep cases/<case>.yaml --law <law> --dt 0.2T_R` "
            "(`results/convergence/largest_dt_over_T_R.csv`).", "",
            _md_table(wide, ".3g"), "", "![largest dt](plots/largest_dt_over_T_R.png)", ""]


def _paper_section(claims: pd.DataFrame, table1: pd.DataFrame | None, energy_check: pd.DataFrame | None) -> list[str]:
    """Reproducing the paper: its claims with verdicts, its Table 1, its figures."""
    counts = claims.verdict.str.replace(r"depends on criterion: .*", "depends on criterion", regex=True).value_counts()
    lines = ["## Reproducing the paper", "",
             "Every number below is recomputed by the reference solver (`results/paper/claims.csv`). "
             "Verdict counts: " + ", ".join(f"{v} {k}" for k, v in counts.items()) + ".", "",
             _md_table(claims[["claim", "where", "paper", "computed", "criterion", "verdict"]].astype(
                 {"paper": str}), ".4g"), ""]
    if table1 is not None:
        t = table1[["case", "geometry", "beta", "Vc_solver_cm_s", "Vc_paper_rule_cm_s", "Vc_paper_cm_s",
                    "ratio_rule_to_paper", "density_kg_m3", "density_for_paper_value_rule"]]
        lines += ["### Table 1: the critical elastic velocity V_c [cm/s]", "",
                  "Recomputed from the table's E, R and eta and the case files' densities, with the solver's "
                  "K_c (x0) and with the paper's rule V_c = 3.7 beta^(5/2) V_D; V_c grows as density^2, so the "
                  "last column is the density the printed value would need (`results/paper/table1.csv`).", "",
                  _md_table(t, ".3g"), ""]
    lines += ["### Figures", "",
              "Fig. 1: phi_1 and phi_2 against K (paper's series dashed, reference solver x0 solid and F0 dotted); "
              "inset: the energy loss xi.", "", "![Fig. 1](paper/fig1_phi.png)", "",
              "Fig. 2 needs the experimental restitution data of the papers the authors cite (Lifshitz & Kolsky, "
              "Kuwabara & Kono, Bridges et al., Gugan); the project has none of it and does not draw the figure.", "",
              "Fig. 3 analogue: eps of every DEM run of every material, engine and geometry, against K.", "",
              "![Fig. 3](paper/fig3_eps_collapse.png)", "",
              "Fig. 4: energy partition in time from the reference solver (lines) and one DEM run per K (markers)."]
    if energy_check is not None:
        lines += ["", "Largest |DEM - reference| of each energy fraction during the contact:", "",
                  _md_table(energy_check, ".2g")]
    lines += ["", "![Fig. 4](paper/fig4_energy.png)", "",
              "Fig. 5: the fracture velocity V_F/V_P against R/L_d (`report/paper/fracture.py`). The paper does "
              "not say which pressure, at which instant, reaches P0. Three readings are drawn: the elastic Hertz "
              "pressure at maximum compression (the default: V_F/V_P > 1, tending to 1 for large bodies, the paper's "
              "trend), the same at the instant of maximum force (higher V_F), and the total force, viscous part "
              "included, over the contact at maximum force, which for small R/L_d gives V_F < V_P: the opposite "
              "size effect. The curve is not universal: it needs P0/E* and the mass factor c_m of M* = c_m rho R^3 "
              "(2 pi/3 for two equal spheres, 4 pi/3 on a plane) besides R/L_d. Higa et al.'s data are not "
              "available to the project.", "", "![Fig. 5](paper/fig5_fracture.png)", ""]
    return lines


#: The report's style sheet: the matrices' cells say pass / fail / n/a in their text (✔ ✘ n/a)
#: and in their colour.
CSS = """
body{font-family:system-ui,sans-serif;max-width:1300px;margin:auto;padding:0 16px;line-height:1.45;color:#222}
h1{font-size:1.6em}h2{margin-top:1.8em;border-bottom:1px solid #ddd;padding-bottom:3px}
table{border-collapse:collapse;margin:8px 0}
td,th{border:1px solid #ccc;padding:2px 6px;font-size:13px}
th{background:#f3f3f3}
img{max-width:100%}
table.matrix td,table.matrix th{padding:4px 10px;text-align:center;white-space:nowrap;font-size:14px}
table.matrix th.build{text-align:left}
table.matrix th.law{font-size:15px}
table.matrix thead th{background:#eef1f5}
table.matrix td.pass{background:#d4edda;color:#155724}
table.matrix td.fail{background:#f8d7da;color:#721c24;font-weight:bold}
table.matrix td.na{background:#e2e3e5;color:#555;font-style:italic}
table.matrix td.none{background:#fff;color:#999}
table.matrix td.compared{background:#fff8e1}
table.matrix .law-start{border-left:3px solid #666}
table.matrix .geometry-start{border-left:2px solid #999}
table.matrix td[title]{cursor:help}
table.matrix .res{font-size:11px;opacity:0.8}
"""


def _write_html(markdown_text: str, path: Path) -> None:
    write_html(markdown_text, path, "Hertz DEM comparison report")


def write_html(markdown_text: str, path: Path, title: str) -> None:
    """The page of `markdown_text` (with tables) in the report's style, written atomically."""
    import markdown

    body = markdown.markdown(markdown_text, extensions=["tables"])
    write_atomically(path, html_page(title, body, CSS))
