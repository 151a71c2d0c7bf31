"""`python -m postprocess.verdict_files [RESULTS]`: the study's verdict line (make study ends its
log with it).

The code lives in `verdict.verdict_files`."""

from verdict.verdict_files import main

if __name__ == "__main__":
    raise SystemExit(main())
