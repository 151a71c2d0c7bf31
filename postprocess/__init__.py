"""The study's command lines, as users type them (`python -m postprocess.<name>`): each module is a
few lines that call the `main` of the module that holds the code (analysis/, verdict/, report/).
"""
