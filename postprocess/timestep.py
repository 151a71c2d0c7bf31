"""`python -m postprocess.timestep ...`: the time-step advisor.

The code lives in `analysis.timestep`."""

from analysis.timestep import main

if __name__ == "__main__":
    raise SystemExit(main())
