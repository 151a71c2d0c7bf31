"""What each engine's restitution keyword delivers against what it is told: the promise table.

For one build, each restitution keyword it has (its code's own, `engines.codes` ``keyword``, and the
keyword laws of `contact_model.laws`, `contact_model.keywords`) is told each e of
a grid; each e runs a ladder (the study's dissipative rungs, aligned to the end its force allows)
whose limit dt -> 0 (`engines.ladder.extrapolate`, the x^{1/4} law's powers) is what the engine
delivers. Beside it: what the keyword's own equation restitutes (the closed form,
`reference.quarter_power_damping`), the engine's error against it (its conformance, which the
study's gate judges) and the promise error, delivered - requested.

Columns of `promise_rows` (results/keywords/promise.csv): code, build, keyword, e_requested, V,
criterion, eps_delivered, eps_own_equation, err_own_equation, err_promise, resolution, problem.
"""

from __future__ import annotations

import math

import numpy as np
import pandas as pd

from engines.ladder import RESOLUTION_FLOOR, extrapolate, powers_of
from records.files import save_figure

COLUMNS = ["code", "build", "keyword", "e_requested", "V", "criterion", "eps_delivered", "eps_own_equation",
           "err_own_equation", "err_promise", "resolution", "problem"]
#: The requested e at which the summary quotes each keyword's promise error.
QUOTED = (0.5, 0.8, 0.95)


def promise_rows(build: str, code: str, keyword, rungs_by_e: dict, metrics: dict, failures: dict) -> list[dict]:
    """One row per requested e.

    Parameters
    ----------
    build, code : str
        The build's id and its engine code.
    keyword : contact_model.keywords.Keyword
        The keyword its runs are of.
    rungs_by_e : dict
        {e: [RunSpec, ...]}: each e's ladder, every rung carrying its reference row (the
        keyword's own equation, `contact_model.keywords.keyword_reference`).
    metrics : dict
        {run name: records.collision_metrics.CollisionMetrics} of the runs that landed.
    failures : dict
        {run name: why it failed} of the others.
    """
    end = keyword.criterion
    rows = []
    for e, rungs in rungs_by_e.items():
        row = rungs[0].reference
        eps_own = row["eps_x0"] if end == "x0" else row["eps_F0"]
        out = {"code": code, "build": build, "keyword": keyword.name, "e_requested": e, "V": rungs[0].velocity,
               "criterion": end, "eps_own_equation": eps_own, "problem": ""}
        failed = [f"{r.name}: {failures[r.name]}" for r in rungs if r.name in failures or r.name not in metrics]
        if failed:
            rows.append({**out, "eps_delivered": math.nan, "err_own_equation": math.nan, "err_promise": math.nan,
                         "resolution": math.nan, "problem": failed[0].splitlines()[0]})
            continue
        h = [r.time_step / r.scales["T_e"] for r in rungs]
        y = [(metrics[r.name].eps_x0 if end == "x0" else metrics[r.name].eps_F0) / eps_own - 1 for r in rungs]
        limit = extrapolate(h, y, powers_of(rungs[0].pair.eta, rungs[0].law, rungs[0].engine))
        delivered = eps_own * (1 + limit.value)
        rows.append({**out, "eps_delivered": delivered, "err_own_equation": limit.value,
                     "err_promise": delivered - e, "resolution": max(limit.estimate, RESOLUTION_FLOOR)})
    return rows


def promise_summary(table: pd.DataFrame) -> pd.DataFrame:
    """Per build and keyword: the largest |promise error| and the e where it occurs, and the
    promise error at each e of QUOTED (NaN where that e was not run).

    Parameters
    ----------
    table : DataFrame
        `promise_rows`' rows (results/keywords/promise.csv): build, keyword, criterion, e_requested,
        err_promise, err_own_equation.
    """
    rows = []
    for (build, _), g in table.groupby(["build", "keyword"], sort=False):
        g = g.dropna(subset=["err_promise"])
        if not len(g):
            continue
        worst = g.loc[g.err_promise.abs().idxmax()]
        row = {"build": build, "keyword": worst.keyword, "criterion": worst.criterion,
               "largest promise error": worst.err_promise, "at e": worst.e_requested,
               "largest |error vs its equation|": g.err_own_equation.abs().max()}
        for e in QUOTED:
            at = g[np.isclose(g.e_requested, e)]
            row[f"error at e = {e:g}"] = float(at.err_promise.iloc[0]) if len(at) else math.nan
        rows.append(row)
    return pd.DataFrame(rows)


def plot_promise(table: pd.DataFrame, path) -> None:
    """eps delivered - e requested against e, one line per build (its keyword), on one figure.

    Parameters
    ----------
    table : DataFrame
        `promise_rows`' rows: build, keyword, criterion, e_requested, err_promise.
    path : str or path-like
        Where the figure is saved (`records.files.save_figure`).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(9, 5))
    markers = "osD^v<>ph"
    for k, ((build, _), g) in enumerate(table.groupby(["build", "keyword"], sort=False)):
        g = g.sort_values("e_requested")
        ax.plot(g.e_requested, g.err_promise, marker=markers[k % len(markers)], mfc="none",
                label=f"{build}: {g.keyword.iloc[0]} ({g.criterion.iloc[0]})")
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_xlabel("e requested (what the keyword is told)")
    ax.set_ylabel("eps delivered - e requested (dt -> 0)")
    ax.set_title("The engines' restitution keywords: what they deliver against what they promise")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)


#: V / vn of `promise_over_velocity`: a decade each side of the velocity a keyword is told.
VELOCITY_RATIOS = (0.01, 0.1, 0.3, 1.0, 3.0, 10.0)


def promise_over_velocity(keywords, restitutions, ratios=VELOCITY_RATIOS) -> pd.DataFrame:
    """What each keyword told e at the velocity vn restitutes at other impact velocities V, by its
    own equation (its engines are gated against that equation at V = vn). A keyword whose force is
    Brilliantov's (form 'half': YADE's en + vn) has K = `Keyword.b` at vn, and K grows as V^{1/5}
    at a fixed coefficient: eps of the viscoelastic law at K (V/vn)^{1/5}, under the keyword's
    criterion. The other keywords' restitution does not depend on V (form 'quarter') or is told
    per velocity (form 'velocity'): no rows.

    A K the reference solver does not take (outside `reference.collision_ode.K_RANGE`, [0, 10]:
    YADE's en + vn told e = 0.05 reaches K = 11.5 at 10 vn) is a row of its own with no eps and
    a `note` saying so ('out of the reference's range: K = 11.5 > 10'), not an error.

    Parameters
    ----------
    keywords : iterable of contact_model.keywords.Keyword
    restitutions : iterable of float
        The e each is told at vn.
    ratios : iterable of float
        V / vn.

    Returns
    -------
    DataFrame with columns keyword, e_requested, V_over_vn, K, eps_own_equation, err_promise
    (eps - e; both NaN where `note` says why), note ('' where eps was solved).
    """
    from reference.collision_ode import K_RANGE, solve_collision

    rows = []
    for keyword in keywords:
        if not keyword.damping_form.is_viscoelastic:  # only a K moves with V (YADE's en + vn)
            continue
        for e in restitutions:
            K_vn = keyword.b(keyword.told_for(float(e)))
            for r in ratios:
                K = K_vn * float(r) ** 0.2
                note = out_of_range(K, K_RANGE)
                eps = math.nan if note else solve_collision(K)[f"eps_{keyword.criterion}"]
                rows.append({"keyword": keyword.name, "e_requested": float(e), "V_over_vn": float(r), "K": K,
                             "eps_own_equation": eps, "err_promise": eps - float(e), "note": note})
    return pd.DataFrame(rows, columns=["keyword", "e_requested", "V_over_vn", "K", "eps_own_equation",
                                       "err_promise", "note"])


def out_of_range(K: float, K_range) -> str:
    """'' when the reference solver takes `K` (within `K_range`, (low, high)), else why not:
    'out of the reference's range: K = 11.5 > 10' (or '< low').

    Parameters
    ----------
    K : float
        The dissipation parameter [-].
    K_range : tuple of float
        (low, high), the reference solver's range of K [-] (`reference.collision_ode.K_RANGE`).
    """
    low, high = K_range
    if K > high:
        return f"out of the reference's range: K = {K:.3g} > {high:g}"
    if K < low:
        return f"out of the reference's range: K = {K:.3g} < {low:g}"
    return ""


def over_velocity_cell(eps: float, note: str) -> str:
    """A cell of the summary's table of `promise_over_velocity`: eps to five decimals, or the note
    saying why there is none.

    Parameters
    ----------
    eps : float
        The restitution [-] (NaN where there is none).
    note : str
        `promise_over_velocity`'s note ('' or NaN where eps was solved).
    """
    return note if isinstance(note, str) and note else f"{eps:.5f}"


def sweep_metrics(sweep) -> tuple[dict, dict]:
    """({run name: records.collision_metrics.CollisionMetrics} of the runs of `sweep` (an
    `engines.Sweep`) that landed, {run name: why} of those that failed): what `promise_rows` takes.

    Parameters
    ----------
    sweep : engines.Sweep
        The runs done: ``dumps`` ({run name: dump path}) and ``failures`` ({run name: why}).
    """
    from records.collision_metrics import collision_metrics
    from records.dump_file import read_dump

    metrics = {}
    for name, path in sweep.dumps.items():
        meta, c = read_dump(path)
        metrics[name] = collision_metrics(c["time"], c["overlap"], c["normal_velocity"], c["normal_force"],
                                          impact_velocity=meta["impact_velocity"])
    return metrics, {name: str(err) for name, err in sweep.failures.items()}
