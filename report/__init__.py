"""The study's pages: the report (`report`, with its matrix, plots, resolution and time-step
sections), the release history's answer (`history_query`) and the paper's figures and tables
(`paper`). They show what analysis/ computed and verdict/ decided, and compute no reference
(analysis.report_references, analysis.timestep_maps); their page shell is
`verdict.verdict_files.html_page`, which the verdict's own pages share. Imports point down
(tests/test_layers.py).
"""
