"""What the engines write and post-processing reads: the study's records.

- `dump_file`: one run's dump (a header of JSON metadata, then t, x, v, F rows);
- `run_manifest`: an engine job's list of dumps with their sha256, and its failed runs;
- `quantities`: the table of the quantities read off a collision (name, unit, gated, extraction,
  reference), which every later step loops over;
- `collision_metrics`: T, A and epsilon read off a dump, and every quantity of the table (`quantities_of`);
- `files`: the one sha256 and the one atomic write both sides use.

The bottom layer of the study's own packages after the physics: reference -> contact_model ->
records -> engines -> analysis, calibration -> verdict -> report -> workflow (tests/test_layers.py
holds it).
"""
