"""The conformance kit: any code's Hertz collision gated as the study gates its engines.

`python -m conformance export` writes a plan of the study's own runs (`conformance.export`);
the user runs it in their code and writes one dump per run; `python -m conformance gate`
reads them (`conformance.dumps`) and gates them (`conformance.gate`). docs/conformance.md is the
guide and the dump format's contract.
"""
