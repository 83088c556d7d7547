"""geoslip.calibrate from Python: a Coulomb law fitted to direct-shear curves.

Reference: the Coulomb law itself (docs/verification.md §4: a uniform slip under a
uniform σn), written here in NumPy independently of geoslip: τ = min(Ks·δ, c + σn·tan φ) with
Ks = 15 000 kPa/m, c = 10 kPa, φ = 28°, at σn = 30, 60 and 120 kPa, δ to 10 mm every 0.1 mm, each
value off by a relative error of standard deviation 2 % (seed 17). Goal: every parameter within 3 %
and inside its 95 % interval, from a file and from a dict alike; one normal stress raises naming c
and φ.
"""

import math
import os

import numpy as np
import pytest

import geoslip

KS, C, PHI = 15000.0, 10.0, 28.0


def write_curves(folder, normal_stresses, seed=17):
    rng = np.random.default_rng(seed)
    lines = ["normal_stress [kPa],slip [mm],shear_stress [kPa]"]
    for s in normal_stresses:
        slip = np.arange(0, 101) * 1e-4
        tau = np.minimum(KS * slip, C + s * math.tan(math.radians(PHI)))
        tau = tau * (1 + 0.02 * rng.standard_normal(tau.size))
        lines += [f"{s},{1e3 * d:.4f},{t:.6f}" for d, t in zip(slip, tau)]
    path = os.path.join(folder, "direct-shear.csv")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")
    return path


def check_recovered(fit):
    for name, truth in [("shear_stiffness", KS), ("cohesion", C), ("friction_angle", PHI)]:
        p = fit.parameters[name]
        assert abs(p.value - truth) < 0.03 * truth, p
        assert p.interval[0] <= truth <= p.interval[1], p
    assert fit.correlation.shape == (3, 3)
    assert np.allclose(np.diag(fit.correlation), 1.0)
    assert fit.law["type"] == "coulomb"
    assert fit.law_block.strip().splitlines()[-1].startswith('law = { type = "coulomb"')


def test_a_file_and_a_dict_give_the_coulomb_law_back(tmp_path):
    write_curves(str(tmp_path), [30.0, 60.0, 120.0])
    (tmp_path / "fit.toml").write_text('test = "direct-shear"\ndata = "direct-shear.csv"\nlaw = "coulomb"\n')
    fit = geoslip.calibrate(tmp_path / "fit.toml", out=tmp_path / "out")
    check_recovered(fit)
    assert (tmp_path / "out" / "fitted-curves.png").is_file()
    assert len(fit.curves) == 3 and fit.curves[0]["measured"].shape == (101,)
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        from_dict = geoslip.calibrate({"test": "direct-shear", "data": "direct-shear.csv", "law": "coulomb"})
    finally:
        os.chdir(cwd)
    for name, p in fit.parameters.items():
        assert from_dict.parameters[name].value == p.value


def test_one_normal_stress_raises_naming_cohesion_and_friction(tmp_path):
    write_curves(str(tmp_path), [60.0])
    (tmp_path / "fit.toml").write_text('test = "direct-shear"\ndata = "direct-shear.csv"\nlaw = "coulomb"\n')
    with pytest.raises(geoslip.CalibrationError) as e:
        geoslip.calibrate(tmp_path / "fit.toml")
    assert "cohesion" in str(e.value) and "friction_angle" in str(e.value), str(e.value)


def test_a_pull_out_curve_that_goes_back_is_refused(tmp_path):
    (tmp_path / "po.csv").write_text(
        "surcharge [kPa],displacement [mm],force [kN/m]\n" + "".join(
            f"{q},{d},{f}\n" for q in (20, 40) for d, f in [(0, 0), (1, 5), (2, 8), (1.5, 6), (3, 9)]
        )
    )
    spec = {"test": "pull-out", "data": "po.csv", "law": "coulomb",
            "pull_out": {"embedded_length": 0.5, "axial_stiffness": 1000.0}}
    cwd = os.getcwd()
    os.chdir(tmp_path)
    try:
        with pytest.raises(geoslip.CalibrationError) as e:
            geoslip.calibrate(spec)
    finally:
        os.chdir(cwd)
    assert "the curve at 20 kPa goes back from 2 to 1.5 mm (its points 3 and 4)" in str(e.value), str(e.value)
