"""Snakemake script: every release's rows in one history (analysis.history): history.csv, the
history page (history.md, history.html) and history.png."""

from pathlib import Path

import pandas as pd

from common import log_to
from analysis.history import history_markdown, history_table, plot_history
from report.report import write_html
from records.files import write_atomically

log = log_to(snakemake.log[0])
table = history_table(pd.concat([pd.read_csv(p, keep_default_na=False, na_values=[""]) for p in snakemake.input],
                                ignore_index=True))
table.to_csv(snakemake.output.csv, index=False, float_format="%.12g")
plot_history(table, snakemake.output.png)
text = history_markdown(table, Path(snakemake.output.png).name)
write_atomically(snakemake.output.md, text)
write_html(text, Path(snakemake.output.html), "Hertz DEM: releases against the checks")
for code in dict.fromkeys(table.code):
    log.info("%s: %d releases, %d checks, %d not passing", code, table[table.code == code].release.nunique(),
             len(table[table.code == code]), int((table[table.code == code].status != "pass").sum()))
