"""Everything the conformance kit takes from the study's post-processing, in one place.

The kit gates a user's dumps exactly as the study gates its engine builds: the same summary rows
(`comparison_rows`, as workflow/scripts/case_summary.py makes them), the same extrapolation to
dt -> 0 with resolution (`extrapolated_rows`), the same checks, verdict and tolerances
(`gate_checks`, `verdict_of`), the same files (`write_verdict_files`) and report (`write_report`).
Every import of `postprocess` by `conformance` is here (the rest of the package imports from this
module), so that moving the post-processing's modules changes this file alone.
"""

from postprocess.comparison import comparison_rows
from postprocess.extrapolation import extrapolated_rows
from postprocess.gate import check_name, gate_checks, verdict_of, write_verdict_files
from postprocess.map_reference import map_errors
from postprocess.report import ReportInputs, write_report
from postprocess.verdict_files import tolerance_problems

__all__ = ["ReportInputs", "check_name", "comparison_rows", "extrapolated_rows", "gate_checks", "map_errors",
           "tolerance_problems", "verdict_of", "write_report", "write_verdict_files"]
