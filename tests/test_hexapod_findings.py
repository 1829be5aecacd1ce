"""Chapter 6's findings (robomill.hexapod.findings) from planted artefacts, and the chapter's
sentences following altered findings (src/robomill/data/templates/ch6_hexapod.yaml, no kernel)."""

import math

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from robomill.findings import Findings
from robomill.hexapod.findings import hexapod_findings
from robomill.pipeline.prose import Prose, load_templates

HEXAPOD = {
    "geometry": {"base_radius_mm": 90.0, "platform_radius_mm": 45.0},
    "platform": {"mass_kg": 0.6},
    "vertical": {"duration_s": 0.25, "actuator": 2, "error_pct": 2.0},
    "programme": {"edges_s": [0.0, 1.0, 3.0], "accel_mm_s2": [[2.0, 3.0, 0.0],
                                                               [-2.0, 3.0, 0.0]]},
    "start_mm": [0.0, 0.0, 50.0], "gravity_m_s2": 9.81, "replay_tolerance_mm": 0.01,
}


def _trajectory(rates=(2.0, 10.0)):
    pos = np.array([[0.0, 0.0, 50.0], [1.0, 2.0, 50.0], [3.0, 4.0, 50.0]])
    return xr.Dataset(
        {"position_mm": (("time", "axis"), pos),
         "replay_tolerance_mm": 0.01, "replay_hold_s": 1.5,
         "instability_rate_per_s": ("mode", list(rates)),
         "vertical_exact_mm": (("time_vertical", "axis"), [[0, 0, 50.0], [0, 0, 51.0]]),
         "vertical_perturbed_mm": (("time_vertical", "axis"), [[0, 0, 50.0], [0, 3.0, 55.0]]),
         "vertical_perturbed_euler_deg": (("time_vertical", "angle"), [[0, 0, 0], [1, 2, 3.0]]),
         "vertical_final_drift_mm": ("axis", [0.0, 3.0, 4.0]),
         "vertical_final_rotvec_deg": ("axis", [0.0, 6.0, 8.0])},
        coords={"time": [0.0, 1.0, 2.0], "axis": ["x", "y", "z"],
                "angle": ["psi", "theta", "phi"]},
        attrs={"solver": "planted"})


def _forces():
    f = np.full((3, 6), 1.5)
    f[1, 2], f[2, 4] = -0.5, 2.5
    return xr.Dataset({"force_N": (("time", "actuator"), f),
                       "vertical_force_N": (("time_vertical", "actuator"), np.full((2, 6), 1.6)),
                       "vertical_perturbed_force_N": (("time_vertical", "actuator"),
                                                      np.full((2, 6), 1.632)),
                       "static_force_N": 1.5})


def _sensitivity(minus=(-0.9, 0.0, 0.0)):
    comp = np.zeros((2, 2, 3))
    comp[:, 1] = [1.0, 0.0, 0.0]
    comp[:, 0] = minus
    return xr.Dataset({"drift_components_per_pct": (("actuator", "axis"),
                                                    [[3.0, 4.0, 0.0], [0.0, 0.0, 6.0]]),
                       "drift_components_mm": (("actuator", "force_error_pct", "axis"), comp)},
                      coords={"actuator": [1, 2], "force_error_pct": [-1.0, 1.0]},
                      attrs={"duration_s": 0.25})


ACCURACY = pd.DataFrame({"position_tolerance_mm": [0.005, 0.01, 0.05],
                         "force_accuracy_pct": [0.001, 0.002, 0.01],
                         "force_accuracy_mN": [0.02, 0.04, 0.2], "worst_actuator": [2, 2, 2],
                         "drift_mm_per_pct": [6.0] * 3, "duration_s": [0.25] * 3})


def _found(**kw):
    args = {"trajectory": _trajectory(), "sensitivity": _sensitivity(), **kw}
    return hexapod_findings(args["trajectory"], _forces(), args["sensitivity"], ACCURACY,
                            hexapod=HEXAPOD)


def test_programme_instability_and_forces_from_planted_artefacts():
    f = _found()
    v = f.values()
    assert v["base_radius_mm"] == 90.0 and v["platform_mass_kg"] == 0.6
    assert f["platform_mass_kg"].config_key == "hexapod.platform.mass_kg"
    assert v["programme_end_mm"] == [3.0, 4.0, 50.0] and v["programme_sideways_mm"] == 5.0
    assert v["replay_hold_s"] == 1.5 and v["n_unstable_modes"] == 2
    assert v["instability_rate_range_per_s"] == [2.0, 10.0]
    assert v["pendulum_rate_per_s"] == pytest.approx(math.sqrt(9.81 / 0.05))
    assert v["efold_ms"] == pytest.approx(100.0)
    assert v["decade_ms"] == pytest.approx(100.0 * math.log(10))
    assert v["start_force_N"] == 1.5 and v["programme_force_range_N"] == [-0.5, 2.5]


def test_vertical_move_beside_the_seed():
    v = _found().values()
    assert v["vertical_force_N"] == 1.6 and v["vertical_perturbed_force_N"] == 1.632
    assert v["vertical_drift_mm"] == pytest.approx(5.0)
    assert v["vertical_drift_z_share_pct"] == pytest.approx(80.0)
    assert v["vertical_rotation_deg"] == pytest.approx(10.0)
    assert v["vertical_euler_deg"] == [1.0, 2.0, 3.0]
    # Rybak n.d.: exact end (0, 0, 54.57), perturbed end (-0.186, -0.0521, 57.864) mm
    seed_drift = np.array([-0.186, -0.0521, 57.864 - 54.57])
    assert v["seed_drift_mm"] == pytest.approx(np.linalg.norm(seed_drift))
    assert v["seed_force_N"] == 1.65 and v["seed_start_height_mm"] == 53.3
    assert len(v["vertical_table_ours"]) == len(v["vertical_table_seed"]) == 11
    assert v["vertical_table_difference"][0] == pytest.approx(1.6 - 1.65)


def test_drift_map_and_force_accuracy():
    v = _found().values()
    assert v["drift_per_pct_range_mm"] == [5.0, 6.0]
    assert v["drift_per_pct_spread_pct"] == pytest.approx(20.0)
    assert v["antisymmetry_error_pct"] == 1.0
    assert v["antisymmetry_pct"] == pytest.approx(10.0)  # |1 - 0.9| / 1
    assert v["accuracy_tolerance_mm"] == 0.01 and v["accuracy_needed_pct"] == 0.002
    assert v["accuracy_needed_mN"] == 0.04 and v["accuracy_duration_s"] == 0.25
    one_sided = _sensitivity().sel(force_error_pct=[1.0])
    w = _found(sensitivity=one_sided).values()
    assert w["antisymmetry_pct"] is None


def test_chapter_6_prose_follows_its_findings():
    refs = {f"ref_{k}": f"[{k}]" for k in ("seed_table1", "trajectory", "actuator_forces",
                                           "drift_vs_exact", "vertical", "drift_map",
                                           "force_accuracy")}
    say = Prose(load_templates("ch6_hexapod"), _found())
    text = " ".join(say(*say.templates, **refs).split())
    assert "a circle of 90 mm" in text and "0.6 kg platform" in text
    assert "carry the platform 5 m sideways" in text
    assert "for **1.50 s** (planted)" in text
    assert "2 unstable modes with growth rates 2.0–10.0 1/s" in text
    assert "grows by e every 100 ms" in text
    assert "A +2 % error in actuator 2 (1.6320 N instead of 1.6000 N) ends 5.00 mm away" in text
    assert "80 % of it along z" in text and "turned by 10.00°" in text
    assert "5.00–6.00 mm over the actuators" in text
    assert "at most 10.0 %" in text
    assert "right to 0.0020 % (0.040 mN of 1.60 N)" in text
    assert "longer by 230 ms" in text
    assert "{" not in text
    stable = Prose(load_templates("ch6_hexapod"),
                   _found(trajectory=_trajectory(rates=(-1.0, -2.0))))
    assert "no unstable mode" in stable("unstable") and stable("accuracy_growth") == ""
    assert stable.findings.values()["efold_ms"] is None
    one_sided = Prose(load_templates("ch6_hexapod"),
                      _found(sensitivity=_sensitivity().sel(force_error_pct=[1.0])))
    assert "both signs" in one_sided("antisymmetry")
    assert "no check" in Prose(load_templates("ch6_hexapod"), Findings("hexapod"))("against_rows")
