"""`python -m conformance export`: a case's runs, planned by the study's own planner, as a plan
that any code can run (plan.json, plan.csv, README.md).

The runs are `engines.plan.plan_runs`'s, exactly as workflow/rules/cases.smk plans a case for
the study's builds (the same ladders of time steps, the same references, the same refusals of
velocities the engines cannot run honestly), for one pseudo build: `BUILD` (your code). The
planner needs a code of `engines.codes` to know what a law means there; the kit gives it the
*carrier*: for a keyword (`--keyword`), the code that offers it (the keyword's own equation is
what is planned), for the model's laws the first code that can express them (their equation is
the same in every code). The carrier never runs anything: it names the law's equation.

Every quantity of the plan is SI. plan.json carries a plan id (the sha256 of its content) that
every dump must carry in its header; the gate refuses a dump of another plan.
"""

from __future__ import annotations

import csv
import hashlib
import io
import json
import math
from pathlib import Path

import yaml

from contact_model import LAW_REGISTRY, load_case
from contact_model.keywords import KEYWORDS
from engines.codes import CODES, KIT_CODES, law_unavailable
from engines.plan import plan_listing, plan_runs
from engines.run_spec import GAP_STEPS, RunSpec
from records.dump_file import COLUMNS, FORMAT_VERSION
from records.files import write_atomically

PROJECT = Path(__file__).resolve().parents[1]
CONFIG = PROJECT / "config" / "config.yaml"
#: The pseudo build the plan's runs belong to: what the runs' names start with.
BUILD = "your_code"
#: The plan's own format (docs/conformance.md).
PLAN_FORMAT = "hertz-dem-conformance-plan"
PLAN_VERSION = 1
#: The quantities a dump records, one sample per step from step 0 to `steps` (records.dump_file).
RECORD = {"time": "s", "overlap": "m", "normal_velocity": "m/s", "normal_force": "N"}


class ExportError(ValueError):
    """What cannot be exported, in words."""


def study_settings(config_path=CONFIG) -> dict:
    """The planning settings and tolerances of config/config.yaml (what the study plans a case with)."""
    config = yaml.safe_load(Path(config_path).read_text())
    keys = ("K_grid", "time_step_factor", "default_law_match_K", "max_overlap_ratio", "ladder", "tolerance")
    return {k: config[k] for k in keys}


#: What a keyword may be told in a plan (`Keyword.told`): a restitution e (--told, or the study's), or
#: its own damping ratio beta, given as it stands (--beta: yade:betan, PFC's dp_nratio where it maps to it).
#: Not eta: a dashpot's eta_n is the study's own translation of e at each velocity, no input of a user's.
EXPORTABLE_TOLD = ("e", "beta")


def carrier_for(laws: list[str], keyword: str | None, beta: float | None = None) -> tuple[str, list[str]]:
    """(the code that carries the plan, the laws to plan): for a keyword its code and the law that runs it
    there ('default' for the code's own keyword, else the keyword's law); else the first code of
    `engines.codes` that expresses every law of `laws`. A keyword told a damping ratio needs `beta`, one told
    e refuses it."""
    if keyword is None and beta is not None:
        raise ExportError("--beta is the damping ratio of a keyword told one (--keyword yade:betan)")
    if keyword is not None:
        if keyword not in KEYWORDS:
            raise ExportError(f"unknown keyword {keyword!r}; known: {', '.join(KEYWORDS)}")
        k = KEYWORDS[keyword]
        exportable = ", ".join(f"{n} (told {kw.told})" for n, kw in KEYWORDS.items() if kw.told in EXPORTABLE_TOLD)
        if k.told not in EXPORTABLE_TOLD:
            raise ExportError(f"keyword {keyword!r} is told {k.told}, which the study computes itself from a "
                              f"restitution at each velocity: it cannot be exported; the kit exports {exportable}")
        if k.told == "beta" and beta is None:
            raise ExportError(f"keyword {keyword!r} is told a damping ratio beta, not a restitution: give it with "
                              "--beta B")
        if k.told == "e" and beta is not None:
            raise ExportError(f"keyword {keyword!r} is told a restitution e (--told), not a damping ratio: "
                              "--beta is for keywords told beta")
        if k.code in KIT_CODES or CODES[k.code].keyword == keyword:  # a code's own keyword: its law `default`
            return k.code, ["default"]
        law = next((n for n, entry in LAW_REGISTRY.items() if entry.keyword == keyword), None)
        if law is None:
            raise ExportError(f"keyword {keyword!r} is no law of the study (contact_model/laws.py)")
        return k.code, [law]
    for law in laws:
        if law not in LAW_REGISTRY:
            raise ExportError(f"unknown law {law!r}; known: {', '.join(LAW_REGISTRY)}")
        if LAW_REGISTRY[law].is_keyword:
            raise ExportError(f"law {law!r} runs an engine's keyword: export it with --keyword "
                              f"(e.g. {next(iter(KEYWORDS))})")
    code = next((c for c in CODES if all(law_unavailable(c, law) is None for law in laws)), None)
    if code is None:
        raise ExportError(f"no code of the study expresses every law of {laws}")
    return code, list(laws)


def law_equation(spec: RunSpec) -> dict:
    """The run's contact law in SI: F = k_n delta^(3/2) + g delta^p d(delta)/dt (clipped at zero where the
    law clips it), M* d2(delta)/dt2 = -F; and in the reference's units, x'' + c x^p x' + (5/4) x^(3/2) = 0.
    g = c M* V / delta_e^(1 + p) (the same force, whatever its form: x = delta/delta_e, tau = t V/delta_e)."""
    pair, scales = spec.pair, spec.scales
    if spec.keyword is not None:
        k = KEYWORDS[spec.keyword]
        form, clipped, c = k.damping_form, k.clipped, float(spec.reference["b"])
    else:
        entry = LAW_REGISTRY[spec.law]
        form, clipped, c = entry.form, bool(entry.clipped), float(spec.K)
    p = form.power
    damped = p is not None and c != 0
    g = c * pair.M * spec.velocity / scales["delta_e"] ** (1.0 + p) if damped else 0.0
    k_n = 4.0 / 3.0 * pair.E * math.sqrt(pair.R)
    if damped:
        text = f"F = k_n delta^(3/2) + g delta^({p:g}) d(delta)/dt" if p else "F = k_n delta^(3/2) + g d(delta)/dt"
    else:
        text = "F = k_n delta^(3/2)"
    return {"equation": text + (", clipped at F >= 0" if clipped else " (no clip: the attractive tail is kept)")
            + "; M* d2(delta)/dt2 = -F while delta > 0, F = 0 otherwise",
            "k_n_N_per_m1.5": k_n, "k_n": "(4/3) E* sqrt(R*)",
            "damping_power": p if damped else None, "damping_coefficient_SI": g,
            "damping_coefficient_unit": f"N s m^-{1 + p:g}" if damped else "",
            "clipped": clipped, "damping_form": form.name,
            "dimensionless": form.equation(f"{c:.10g}" if damped else None),
            "dimensionless_coefficient": c if damped else 0.0}


def _body(body) -> dict:
    if body.is_plane:
        return {"plane": True, "radius_m": None, "density_kg_m3": None, "mass_kg": None,
                "young_Pa": body.young, "poisson": body.poisson}
    return {"plane": False, "radius_m": body.radius, "density_kg_m3": body.density, "mass_kg": body.mass,
            "young_Pa": body.young, "poisson": body.poisson}


def run_entry(spec: RunSpec, rung: int) -> dict:
    """One run of the plan: everything a code needs to set it up, run it and record it, SI."""
    pair, s, state = spec.pair, spec.scales, spec.initial_state()
    v1, v2 = spec.initial_velocities()
    initial = {"x1_m": state["x1"], "v1_m_s": v1,
               "x2_m": 0.0 if pair.body_2.is_plane else state["x2"], "v2_m_s": v2}
    return {
        "name": spec.name, "ladder": spec.ladder, "rung": rung, "case": spec.case, "build": spec.build,
        "carrier_code": spec.engine, "law": spec.law, "keyword": spec.keyword, "geometry": pair.geometry,
        "represents": list(spec.represents), "told_e": spec.matched_restitution,
        # a keyword told its own damping ratio (yade:betan, --beta): beta as given [-], no restitution asked
        "told_beta": spec.told_input,
        "body_1": _body(pair.body_1), "body_2": _body(pair.body_2),
        "effective": {"E_star_Pa": pair.E, "R_star_m": pair.R, "M_star_kg": pair.M}, "eta_Pa_s": pair.eta,
        "law_equation": law_equation(spec),
        "impact_velocity_m_s": spec.velocity, "K": spec.K,
        "hertz_scales": {"delta_e_m": s["delta_e"], "T_e_s": s["T_e"], "A_e_m2": s["A_e"], "F_e_N": s["F_e"]},
        "time_step_factor": spec.time_step_factor, "dt_s": spec.time_step, "steps": spec.steps(),
        "samples": spec.steps() + 1, "contact_starts_s": (GAP_STEPS + spec.start_phase) * spec.time_step,
        "initial": initial, "record": RECORD, "dump": f"dumps/{spec.name}.csv",
        "reference": spec.reference, "roundoff_floor": spec.roundoff_floor(),
    }


def plan_id(plan: dict) -> str:
    """The sha256 of the plan's content (every key but plan_id), canonical JSON."""
    body = {k: v for k, v in plan.items() if k != "plan_id"}
    return hashlib.sha256(json.dumps(body, sort_keys=True, allow_nan=True).encode()).hexdigest()


def export_plan(case_paths, laws=("viscoelastic",), keyword: str | None = None, K_grid=None,
                told: float | None = None, settings: dict | None = None, beta: float | None = None) -> dict:
    """The plan of `case_paths` for one pseudo build (`BUILD`): the study's `plan_runs` and `plan_listing`.
    `told`: the restitution a keyword told e is asked for; `beta`: the damping ratio a keyword told beta
    is given (yade:betan), as it stands."""
    settings = dict(settings or study_settings())
    if K_grid:
        settings["K_grid"] = [float(k) for k in K_grid]
    if told is not None and beta is not None:
        raise ExportError("--told (a restitution) and --beta (a damping ratio) exclude each other")
    code, planned_laws = carrier_for(list(laws), keyword, beta)
    build = {"id": BUILD, "code": code}
    runs, skipped, not_available, notes, cases = [], [], [], [], []
    for path in case_paths:
        case = load_case(path)
        plan = plan_runs(case, [build], planned_laws, settings["K_grid"], settings["time_step_factor"],
                         settings["default_law_match_K"], settings["max_overlap_ratio"], ladder=settings["ladder"],
                         told=told, told_input=beta)
        listing = plan_listing(case, plan)
        cases.append({"case": case.name, "file": str(path), "case_sha256": listing["case_sha256"]})
        rungs: dict[str, int] = {}
        for spec in plan.runs:
            rungs[spec.ladder] = rungs.get(spec.ladder, -1) + 1
            runs.append(run_entry(spec, rungs[spec.ladder]))
        skipped += plan.skipped
        not_available += plan.not_available
        notes += plan.notes
    if not runs:
        raise ExportError("nothing to run: " + "; ".join(n["reason"] for n in not_available))
    plan = {"format": PLAN_FORMAT, "version": PLAN_VERSION, "dump_format": f"hertz-dem-dump: {FORMAT_VERSION}",
            "dump_columns": list(COLUMNS), "build": BUILD, "carrier_code": code, "laws": planned_laws,
            "keyword": keyword, "told_beta": beta, "settings": settings, "tolerance": settings["tolerance"],
            "cases": cases,
            "runs": runs, "not_run": skipped, "not_available": not_available, "notes": notes}
    plan["plan_id"] = plan_id(plan)
    return plan


#: plan.csv's columns: (column, how it is read off a run entry).
CSV_COLUMNS = [
    ("run", lambda r: r["name"]), ("ladder", lambda r: r["ladder"]), ("rung", lambda r: r["rung"]),
    ("case", lambda r: r["case"]), ("law", lambda r: r["law"]), ("keyword", lambda r: r["keyword"] or ""),
    ("geometry", lambda r: r["geometry"]), ("criteria", lambda r: " ".join(r["represents"])),
    ("told_e", lambda r: "" if r["told_e"] is None else r["told_e"]),
    ("told_beta", lambda r: "" if r.get("told_beta") is None else r["told_beta"]),
    ("R1_m", lambda r: r["body_1"]["radius_m"]), ("rho1_kg_m3", lambda r: r["body_1"]["density_kg_m3"]),
    ("m1_kg", lambda r: r["body_1"]["mass_kg"]), ("E1_Pa", lambda r: r["body_1"]["young_Pa"]),
    ("nu1", lambda r: r["body_1"]["poisson"]),
    ("R2_m", lambda r: r["body_2"]["radius_m"]), ("rho2_kg_m3", lambda r: r["body_2"]["density_kg_m3"]),
    ("m2_kg", lambda r: r["body_2"]["mass_kg"]), ("E2_Pa", lambda r: r["body_2"]["young_Pa"]),
    ("nu2", lambda r: r["body_2"]["poisson"]),
    ("E_star_Pa", lambda r: r["effective"]["E_star_Pa"]), ("R_star_m", lambda r: r["effective"]["R_star_m"]),
    ("M_star_kg", lambda r: r["effective"]["M_star_kg"]), ("eta_Pa_s", lambda r: r["eta_Pa_s"]),
    ("k_n_N_m1.5", lambda r: r["law_equation"]["k_n_N_per_m1.5"]),
    ("damping_power", lambda r: r["law_equation"]["damping_power"]),
    ("damping_coefficient_SI", lambda r: r["law_equation"]["damping_coefficient_SI"]),
    ("clipped", lambda r: r["law_equation"]["clipped"]),
    ("V_m_s", lambda r: r["impact_velocity_m_s"]), ("K", lambda r: r["K"]),
    ("delta_e_m", lambda r: r["hertz_scales"]["delta_e_m"]), ("T_e_s", lambda r: r["hertz_scales"]["T_e_s"]),
    ("dt_s", lambda r: r["dt_s"]), ("steps", lambda r: r["steps"]), ("samples", lambda r: r["samples"]),
    ("x1_m", lambda r: r["initial"]["x1_m"]), ("v1_m_s", lambda r: r["initial"]["v1_m_s"]),
    ("x2_m", lambda r: r["initial"]["x2_m"]), ("v2_m_s", lambda r: r["initial"]["v2_m_s"]),
    ("dump", lambda r: r["dump"]),
]


def plan_csv(plan: dict) -> str:
    """plan.csv: one row per run, every quantity SI, its unit in the column's name ('' for none)."""
    buf = io.StringIO()
    w = csv.writer(buf, lineterminator="\n")
    w.writerow([c for c, _ in CSV_COLUMNS])
    for r in plan["runs"]:
        w.writerow(["" if v is None else (repr(v) if isinstance(v, float) else v)
                    for v in (get(r) for _, get in CSV_COLUMNS)])
    return buf.getvalue()


def readme(plan: dict) -> str:
    """README.md of an exported plan: what to run and record, in words."""
    runs = plan["runs"]
    ladders = list(dict.fromkeys(r["ladder"] for r in runs))
    law_lines = []
    for ladder in ladders:
        r = next(x for x in runs if x["ladder"] == ladder)
        eq = r["law_equation"]
        told = f", told e = {r['told_e']:.6g}" if r["told_e"] is not None else ""
        if r.get("told_beta") is not None:
            told = f", told beta = {r['told_beta']:.6g} (`told_beta`, a damping ratio: no restitution asked)"
        law_lines.append(f"- `{ladder}`: {r['geometry']}, V = {r['impact_velocity_m_s']:.9g} m/s, K = {r['K']:.6g}"
                         f"{told}; {eq['equation']} with k_n = {eq['k_n_N_per_m1.5']:.9g} N/m^1.5"
                         + (f", g = {eq['damping_coefficient_SI']:.9g} {eq['damping_coefficient_unit']}"
                            if eq["damping_power"] is not None else "")
                         + f" ({eq['dimensionless']}); rungs dt = "
                         + ", ".join(f"{x['dt_s']:.6g} s ({x['steps']} steps)"
                                     for x in runs if x["ladder"] == ladder))
    tol = ", ".join(f"{q} {v:g}" for q, v in plan["tolerance"].items())
    return "\n".join([
        f"# Conformance plan {plan['plan_id'][:12]}", "",
        f"Cases: {', '.join(c['case'] for c in plan['cases'])}; laws: {', '.join(plan['laws'])}"
        + (f" (keyword `{plan['keyword']}`)" if plan["keyword"] else "") + f"; {len(runs)} runs in "
        f"{len(ladders)} ladders. Planned by the study's own planner (engines.plan), for the pseudo build "
        f"`{plan['build']}`. Full guide: docs/conformance.md in the study's repository.", "",
        "## What to run", "",
        "Every run is one head-on collision along x, the line of centres. Body 1 is a sphere moving +x; body 2 "
        "a sphere moving -x (centre of mass at rest), or the fixed plane x = 0 (sphere-plane). The overlap is "
        "delta = R1 + R2 - (x2 - x1) for two spheres, delta = R1 + x1 for the plane; the normal force F acts "
        "while delta > 0, -F on body 1 and +F on body 2. Each run's `law_equation` gives F in SI; "
        "`effective` gives E*, R*, M* (1/R* = 1/R1 + 1/R2, 1/M* = 1/m1 + 1/m2; a plane: R2 = m2 = infinity).", "",
        "Start at t = 0 from `initial` (x1, v1, x2, v2), with the time step `dt_s`, for `steps` steps. The "
        "bodies touch half a step after sample 20 (`contact_starts_s`): do not move them, do not change dt. "
        "Give your code the material (radius, density, E, nu of each body, or E* directly) and the law's "
        "coefficients (k_n, g, or for a keyword the e it is told, `told_e`, or the damping ratio it is told, "
        "`told_beta`) in its own words.", "",
        "## What to record", "",
        f"One sample per step, from step 0 to step `steps` (`samples` rows): {', '.join(RECORD)} in "
        "SI (s, m, m/s, N): overlap negative before contact (minus the gap), normal_velocity = d(delta)/dt "
        "(positive while approaching), normal_force positive when repulsive. Write each run to its `dump` "
        f"(dumps/<run>.csv) in the format `# hertz-dem-dump: {FORMAT_VERSION}`, with a header line "
        f"`# plan_id: \"{plan['plan_id']}\"` and `# run: \"<run name>\"` (optionally `# engine_version: "
        "\"...\"`). Or write plain CSV files and a columns.yaml saying which column is what, in which unit "
        "(docs/conformance.md).", "",
        "## Then", "",
        "`python -m conformance gate <this folder>`: report.md, report.html, verdict.json, junit.xml; exit 0 on "
        f"PASS, 1 on FAIL, 2 when a dump cannot be used. Tolerances (relative, dt -> 0 against the reference): "
        f"{tol}.", "",
        "## The runs", "", *law_lines, "",
        *(["## Not run", "", *(f"- {n.get('geometry', '')} K = {n.get('K', float('nan')):.3g}: {n['reason']}"
                               for n in plan["not_run"]), ""] if plan["not_run"] else []),
        *(["## Notes", "", *(f"- {n}" for n in plan["notes"]), ""] if plan["notes"] else []),
    ])


def write_plan(plan: dict, out: Path) -> None:
    """plan.json, plan.csv and README.md into `out` (and an empty dumps/)."""
    out = Path(out)
    (out / "dumps").mkdir(parents=True, exist_ok=True)
    write_atomically(out / "plan.json", json.dumps(plan, indent=1) + "\n")
    write_atomically(out / "plan.csv", plan_csv(plan))
    write_atomically(out / "README.md", readme(plan) + "\n")
