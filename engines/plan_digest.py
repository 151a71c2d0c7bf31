"""A case's plan as a rule's parameter that Snakemake names by its digest.

Snakemake records a rule's params by their ``repr`` and, when they change, prints the old and the
new side by side as the job's reason: a case's plan listing (`engines.plan.plan_listing`, every run
with its reference row) is tens of KB on one line of the log, which says nothing to a reader. As a
`PlanListing` it is the same dict to the job's script, and ``repr`` gives the case and the sha256
of its content: a changed plan still changes the param (Snakemake reruns the job), and the log says
"<plan of case 'steel': 48 runs, sha256 3f2a...>" instead.
"""

from __future__ import annotations

import hashlib
import json


class PlanListing(dict):
    """A plan listing (a dict: case, runs, not_run, ...) whose ``repr`` is its case, run count and
    sha256 (of its JSON with sorted keys), for Snakemake's params and their log line."""

    @property
    def sha256(self) -> str:
        """sha256 of the listing's JSON (keys sorted; what is not JSON written by its ``str``)."""
        return hashlib.sha256(json.dumps(self, sort_keys=True, default=str).encode()).hexdigest()

    def __repr__(self) -> str:
        return f"<plan of case {self.get('case')!r}: {len(self.get('runs', []))} runs, sha256 {self.sha256}>"

    def __reduce__(self):  # pickled for the job's script as the dict it is, rebuilt as a PlanListing
        return (PlanListing, (dict(self),))
