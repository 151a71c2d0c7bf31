"""The study's pages: the report (`report`, with its matrix, plots, resolution and time-step
sections), the release history's answer (`history_query`), the HTML page shell (`page`) and the
paper's figures and tables (`paper`). They show what analysis/ computed and verdict/ decided;
they compute no reference (tests/test_layers.py: imports point down).
"""
