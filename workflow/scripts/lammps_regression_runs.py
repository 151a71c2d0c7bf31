"""Snakemake script: the LAMMPS regression cases (engines.lammps.regression_cases) in one LAMMPS build."""

from common import start_rule
from engines.builds import Build
from engines.lammps import run_regression_cases
from engines.plan import rungs_of
from analysis.regressions import regression_table
from records.run_manifest import write_manifest

log = start_rule(snakemake)
build = Build(**snakemake.params.build)
cases, sweep = run_regression_cases(snakemake.output.runs, executable=build.executable, build=build.id,
                                    timeout_floor_s=snakemake.params.timeout_floor_s)
write_manifest(snakemake.output.manifest, list(sweep.dumps.values()),
               sweep.failed_runs([r for case in cases for spec in (case.control, case.run) for r in rungs_of(spec)]),
               case="lammps regressions", build=build.id, engine=build.code, engine_seconds=sweep.engine_seconds)
log.info("%d runs landed, %d failed; engine processes %.2f s", len(sweep.dumps), len(sweep.failures),
         sweep.engine_seconds)
table = regression_table(cases, sweep, build.id)
table.to_csv(snakemake.output.csv, index=False, float_format="%.6g")
for row in table.to_dict("records"):
    log.info("%s %s %s: err_T %.3g err_A %.3g err_eps %.3g %s", row["build"], row["case"], row["role"],
             row["err_T"], row["err_A"], row["err_eps"], row["problem"])
