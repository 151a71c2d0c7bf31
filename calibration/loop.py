"""The DEM runs that close the calibration's loop: the calibrated contact in an engine at every
measured velocity (their results are read by `calibration.outputs.loop_table`).

Kept apart from `calibration.outputs` so that the job that runs them does not import the
plotting and table libraries (~2 s a process).
"""

from __future__ import annotations

from contact_model.case_file import Case
from engines.run_spec import RunSpec

from .case_calibration import calibrated_pair

#: The law each criterion's DEM check runs: x0 keeps the attractive tail, F0 separates at zero force.
LOOP_LAW = {"x0": "viscoelastic", "F0": "viscoelastic_clipped"}


def loop_runs(case: Case, summary: dict, engine: str, time_step_factor: float, build: str = "") -> list[RunSpec]:
    """The DEM runs that close the loop: the calibrated pair of each criterion at every measured
    velocity, in the law that represents that criterion (`LOOP_LAW`); eta [Pa s] from the fit
    summary's `fits[criterion]["eta_Pa_s"]`."""
    runs = []
    for criterion, law in LOOP_LAW.items():
        pair = calibrated_pair(case.pairs[0], summary["fits"][criterion]["eta_Pa_s"])
        for v in sorted(set(case.measurements.velocity.tolist())):
            runs.append(RunSpec(f"{case.name}-calibration", engine, law, pair, v, time_step_factor, label=criterion,
                                build=build))
    return runs
