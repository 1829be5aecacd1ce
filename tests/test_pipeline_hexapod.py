"""Chapter 6 artefacts on the tiny run: shapes, units, the seed's behaviour, antisymmetry."""

import numpy as np
import pytest

from robomill.io import open_artefact

pytestmark = pytest.mark.pipeline


def test_hexapod_artefacts(tiny_run, tiny_config):
    out = tiny_run / "results/hexapod"
    traj = open_artefact(out / "trajectory.nc")
    frc = open_artefact(out / "forces.nc")
    sens = open_artefact(out / "sensitivity.nc")
    cfg = tiny_config["hexapod"]
    # the programme ends where the seed's accelerations take it
    np.testing.assert_allclose(traj["position_mm"].isel(time=-1), [4.0, 40.0, 53.3], atol=1e-9)
    assert frc["force_N"].sizes == {"time": traj.sizes["time"], "actuator": 6}
    # the vertical move of the symmetric platform: six equal forces, near the static one
    # (the programme itself starts accelerating, so its forces differ from actuator to actuator)
    vertical = frc["vertical_force_N"].isel(time_vertical=0)
    np.testing.assert_allclose(vertical, vertical.isel(actuator=0), rtol=1e-9)
    np.testing.assert_allclose(vertical, float(frc["static_force_N"]), rtol=0.01)
    # replay tracks the command until the instability takes over
    assert float(traj["replay_hold_s"]) > 1.0
    # the seed's experiment: millimetres and degrees from +1 % in one actuator
    assert 1.0 < np.linalg.norm(traj["vertical_final_drift_mm"]) < 10.0
    assert 1.0 < np.linalg.norm(traj["vertical_final_rotvec_deg"]) < 10.0
    # the sensitivity map: dims, and antisymmetry to first order for ±1 %
    assert sens["drift_mm"].dims == ("actuator", "force_error_pct")
    assert list(sens["actuator"].values) == cfg["sensitivity"]["actuators"]
    d = sens["drift_components_mm"]
    plus, minus = d.sel(force_error_pct=1.0), d.sel(force_error_pct=-1.0)
    assert float(np.abs(plus + minus).max()) < 0.1 * float(np.abs(plus).max())
    for name in ("drift_mm", "tilt_deg"):
        assert sens[name].attrs["units"] and sens[name].attrs["long_name"]


def test_ch6_hexapod_chapter(tiny_run):
    html = tiny_run / "results/chapters/ch6_hexapod.html"
    assert html.exists() and "Traceback" not in html.read_text()
    figures = sorted(p.name for p in (tiny_run / "results/figures/ch6_hexapod").glob("*.png"))
    assert len(figures) == 4 and all(f.startswith("fig6_1") for f in figures), figures
