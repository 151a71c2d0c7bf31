"""Reproducing "Hertz beyond expectations": its Table 1, its claims, its figures (1, 3, 4, 5)."""
