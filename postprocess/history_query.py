"""`python -m postprocess.history_query ...`: a case's answer from the release history.

The code lives in `report.history_query`."""

from report.history_query import main

if __name__ == "__main__":
    raise SystemExit(main())
