"""Snakemake script: the promise table of every build's restitution keyword (promise.csv), its
summary (promise.md) and its figure (promise.png); postprocess.keyword_promise."""

from pathlib import Path

import pandas as pd

from common import log_to
from postprocess.keyword_promise import plot_promise, promise_summary
from records.files import write_atomically

log = log_to(snakemake.log[0])
table = pd.concat([pd.read_csv(p) for p in snakemake.input], ignore_index=True)
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
if len(problems):
    lines += ["Not run (the code refuses that e) or failed:", "", *(f"- {r.build} e = {r.e_requested:g}: {r.problem}"
                                         for r in problems.itertuples()), ""]
write_atomically(snakemake.output.md, "\n".join(lines))
log.info("promise table: %d rows, %d builds", len(table), table.build.nunique())
