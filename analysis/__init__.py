"""Analysis of the engines' records: what the gate judges and the reports show.

Extrapolation of the ladders to dt -> 0 (`extrapolation`), comparison with the reference
(`comparison`, `map_reference`), convergence tables (`convergence`), the energy partition
(`energy`), the keywords' promise (`keyword_promise`), restitution as a function of velocity
(`restitution_of_velocity`), the time-step advisor (`timestep`), the release history's tables
(`history`), the engines' regression cases (`regressions`), and the helpers the gate judges with
(`checks`). Imports records/, reference/, engines/ and contact_model/ only (tests/test_layers.py).
"""
