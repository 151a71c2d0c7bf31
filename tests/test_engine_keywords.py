"""Each engine build's keywords (the law 'default' and the keyword laws of contact_model.laws),
unmodified, against their own equation: a ladder of four rungs aligned to the end its force
allows, extrapolated to dt -> 0 with the x^(1/4) law's powers, meets the closed form of
x'' + b x^(1/4) x' + (5/4) x^(3/2) = 0 (reference.quarter_power_damping) at the b its code computes
from e (YADE's en + vn: Brilliantov's law at the K its Pade gives, its rungs refined by that K),
to 1e-6 with its resolution added, at a lightly and a strongly damping e. A build whose
release predates a keyword (contact_model.keywords `since`) is run too: its engine must refuse it,
which is what the plan's leaving it out rests on."""

import math
import shutil
from pathlib import Path

import pytest
import yaml

from contact_model.keywords import KEYWORDS, keyword_reference, missing_in
from contact_model.laws import KEYWORD_LAWS
from engine_cases import VELOCITY, dump_metrics, missing, steel_pair
from engines import RunSpec, run_sweep
from engines.builds import check_build, load_builds
from engines.codes import CODES, keyword_of, law_unavailable
from engines.ladder import RESOLUTION_FLOOR, extrapolate, powers_of
from engines.plan import keyword_own_K, ladder_factors

ROOT = Path(__file__).resolve().parents[1]
BUILDS = load_builds(yaml.safe_load((ROOT / "config" / "config.yaml").read_text())["builds"], ROOT)
FACTORS = (250, 500, 1000, 2000)
#: What a release that predates a keyword says when asked for it.
REFUSAL = {"lammps": "unrecognized damping model",  # LAMMPS 29 Sep 2021, damping coeff_restitution
           "yade": "No such attribute: vn"}  # YADE 2023.02a, Ip2_FrictMat_FrictMat_MindlinPhys(vn=...)


#: (build, keyword law) of every keyword law each build's code has.
BUILD_LAWS = [(b, law) for b in BUILDS for law in KEYWORD_LAWS if law_unavailable(b.code, law) is None]


@pytest.mark.parametrize("e", [0.8, 0.3])
@pytest.mark.parametrize("build, law", BUILD_LAWS, ids=[f"{b.id}-{law}" for b, law in BUILD_LAWS])
def test_the_keyword_computes_its_own_equation(build, law, e, tmp_path):
    if shutil.which(build.executable) is None:
        missing(f"{build.executable} is not installed ({build.code}); {CODES[build.code].install_hint}")
    keyword = KEYWORDS[keyword_of(law, build.code)]
    geometry = "sphere-plane" if build.code == "liggghts" else "sphere-sphere"
    pair = steel_pair(geometry, 0.1)
    row = keyword_reference(keyword.name, e, pair.dissipation_parameter(VELOCITY))
    specs = [RunSpec("kw", build.code, law, pair, VELOCITY, f, matched_restitution=e, build=build.id,
                     reference=row) for f in ladder_factors({"dissipative": FACTORS}, law, 0.0,
                                                            keyword_own_K(keyword.name, row))]
    sweep = run_sweep(build, specs, tmp_path / build.id, timeout_floor_s=120)
    if missing_in(keyword.name, check_build(build)):  # a release before the keyword: the engine refuses it
        assert not sweep.dumps and specs[0].name in sweep.failures
        assert REFUSAL[build.code] in str(sweep.failures[specs[0].name])
        return
    assert not sweep.failures, sweep.failures
    end = keyword.criterion
    errors = {"T": [], "A": [], "eps": []}
    for spec in specs:
        _, m = dump_metrics(sweep.dumps[spec.name])
        s = spec.scales
        T, eps = (m.T_x0, m.eps_x0) if end == "x0" else (m.T_F0, m.eps_F0)
        tau, eps_ref = (row["tau_0"], row["eps_x0"]) if end == "x0" else (row["tau_f"], row["eps_F0"])
        errors["T"].append(T / (tau * s["delta_e"] / VELOCITY) - 1)
        errors["A"].append(m.delta_max / (row["x_max"] * s["delta_e"]) - 1)
        errors["eps"].append(eps / eps_ref - 1)
    h = [spec.time_step / spec.scales["T_e"] for spec in specs]
    for q, y in errors.items():
        x = extrapolate(h, y, powers_of(pair.eta, law, build.code))
        resolution = max(x.estimate, RESOLUTION_FLOOR)
        assert abs(x.value) + resolution <= 1e-6, (q, x, y)
        assert abs(y[-1]) > 10 * abs(x.value) or abs(y[-1]) < 1e-6  # the ladder removed the step's own error
    assert math.isfinite(row["eps_x0"] if end == "x0" else row["eps_F0"])
