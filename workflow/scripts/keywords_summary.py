"""Snakemake script: the promise table of every build's restitution keyword (promise.csv), its
summary (promise.md) and its figure (promise.png); analysis.keyword_promise."""

from pathlib import Path

import pandas as pd

from common import log_to
from contact_model.measurement_file import load_measurements
from contact_model.keywords import KEYWORDS
from analysis.keyword_promise import over_velocity_cell, plot_promise, promise_over_velocity, promise_summary
from analysis.restitution_of_velocity import FOLLOWS_R2, fit_forms, plot_forms
from records.files import save_figure, write_atomically

log = log_to(snakemake.log[0])
table = pd.concat([pd.read_csv(p) for p in snakemake.input.rows], ignore_index=True)
table.to_csv(snakemake.output.csv, index=False, float_format="%.12g")
summary = promise_summary(table)
plot_promise(table, snakemake.output.png)
problems = table[table.problem.fillna("") != ""]
lines = ["# The engines' restitution keywords: what they deliver against what they are told", "",
         "Each build's keyword (docs/keywords.md) told each e, one ladder each, extrapolated to dt -> 0 "
         "(`promise.csv`: every e). `largest |error vs its equation|`: the engine against the keyword's own "
         "equation (its conformance, gated in the study); the promise errors: delivered - requested.", "",
         summary.to_markdown(index=False, floatfmt=".3g") if len(summary) else "(no keyword delivered a value)", "",
         f"![promise]({Path(snakemake.output.png).name})", ""]
# A keyword told e at a velocity (YADE's en + vn): what it restitutes away from that velocity.
over_v = promise_over_velocity([KEYWORDS[k] for k in dict.fromkeys(table.keyword)],
                               sorted({float(e) for e in table.e_requested}))
over_v.to_csv(snakemake.output.over_velocity, index=False, float_format="%.12g")
for name, g in over_v.groupby("keyword", sort=False):
    # a K beyond the reference solver's range is a cell that says so, not a crash of the target
    cells = g.assign(cell=[over_velocity_cell(e, n) for e, n in zip(g.eps_own_equation, g.note)])
    grid = cells.pivot(index="e_requested", columns="V_over_vn", values="cell")
    grid.columns = [f"V = {c:g} vn" for c in grid.columns]
    grid.index = [f"{e:g}" for e in grid.index]
    lines += [f"## {KEYWORDS[name].written}: away from the velocity it is told", "",
              "Its force is Brilliantov's, so its restitution falls with V as the viscoelastic law's: told e at vn, "
              "it restitutes (its own equation, which its engines meet at V = vn; `promise_over_velocity.csv`):", "",
              grid.rename_axis("told e").reset_index().to_markdown(index=False, disable_numparse=True), ""]
    for note in dict.fromkeys(n for n in g.note if n):
        log.warning("%s: %s", KEYWORDS[name].written, note)
if len(problems):
    lines += ["Not run (the code refuses that e) or failed:", "", *(f"- {r.build} e = {r.e_requested:g}: {r.problem}"
                                         for r in problems.itertuples()), ""]
# Which damping form can follow a measured eps(V): each fitted to the measurements.
if snakemake.input.measured:
    data = load_measurements(snakemake.input.measured)
    fits = fit_forms(data.velocity, data.restitution)
    fits.to_csv(snakemake.output.forms, index=False, float_format="%.8g")
    plot_forms(data.velocity, data.restitution, fits, snakemake.output.forms_png,
               f"Each damping form fitted to {Path(data.path).name} ({len(data)} points)")
    followers = fits[fits.follows]
    lines += ["## Which keyword can follow a measured eps(V)?", "",
              f"Each damping form's one coefficient fitted to `{data.path}` ({len(data)} points, "
              f"{data.velocity.min():g} to {data.velocity.max():g} m/s; `eps_of_velocity.csv`). A form follows the "
              f"measurements when it explains at least {FOLLOWS_R2:.0%} of their variation (R² >= {FOLLOWS_R2:g}) "
              "with the measured trend.", "",
              fits.drop(columns=["coefficient"]).to_markdown(index=False, floatfmt=".4g"), "",
              ("Follows: " + "; ".join(f"{r.form} ({r.criterion}): {r.keywords}" for r in followers.itertuples())
               if len(followers) else "No form follows these measurements.") + "."
              + (" The restitution keywords give one eps at every velocity, and a linear dashpot's eps rises with V: "
                 "neither can follow an eps that falls with V."
                 if data.restitution[data.velocity.argmax()] < data.restitution[data.velocity.argmin()] else ""),
              "", f"![eps(V)]({Path(snakemake.output.forms_png).name})", ""]
else:  # nothing to fit: an empty table, and a figure that says so
    pd.DataFrame(columns=["form", "criterion", "keywords", "coefficient", "value", "rms_residual",
                          "max_abs_residual", "R2", "eps_at_V_min", "eps_at_V_max", "follows"]).to_csv(
        snakemake.output.forms, index=False)
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig = plt.figure(figsize=(6, 2))
    fig.text(0.5, 0.5, "no measurements (config keywords.measured: null)", ha="center")
    save_figure(fig, snakemake.output.forms_png)
write_atomically(snakemake.output.md, "\n".join(lines))
log.info("promise table: %d rows, %d builds", len(table), table.build.nunique())
