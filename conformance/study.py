"""Everything the conformance kit takes from the study's post-processing, in one place.

The kit gates a user's dumps exactly as the study gates its engine builds: the same summary rows
(`comparison_rows`, as workflow/scripts/case_summary.py makes them), the same extrapolation to
dt -> 0 with resolution (`extrapolated_rows`), the same checks, verdict and tolerances
(`gate_checks`, `verdict_of`), the same files (`write_verdict_files`) and report (`write_report`).
Every import of the analysis, verdict and report layers by `conformance` is here (the rest of
the package imports from this module), so that moving their modules changes this file alone.
"""

from analysis.comparison import comparison_rows
from analysis.extrapolation import extrapolated_rows
from verdict.gate import check_name, gate_checks, verdict_of, write_verdict_files
from analysis.map_reference import map_errors
from report.report import ReportInputs, write_report
from verdict.verdict_files import tolerance_problems


__all__ = ["ReportInputs", "check_name", "comparison_rows", "extrapolated_rows", "gate_checks", "map_errors",
           "tolerance_problems", "verdict_of", "write_report", "write_verdict_files"]
