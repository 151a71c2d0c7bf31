"""`python -m postprocess.compare ...`: compare two studies and gate the candidate.

The code lives in `verdict.compare`."""

from verdict.compare import main

if __name__ == "__main__":
    raise SystemExit(main())
