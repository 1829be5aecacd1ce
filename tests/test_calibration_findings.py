"""Chapter 1's findings (robomill.calibration.findings) from a planted model and accuracy
table, and the chapter's sentences following them (src/robomill/data/templates/ch1.yaml)."""

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from robomill.calibration.findings import calibration_findings
from robomill.findings import Findings
from robomill.pipeline.prose import Prose, load_templates

ARCSEC = np.pi / 180 / 3600


def _model(gravity="cell mass_model"):
    joints = np.arange(1, 4)
    forms = ["polynomial", "fourier", "fourier+polynomial"]
    val = np.array([[10.0, 8.0, 6.0], [9.0, 12.0, 7.0], [5.0, 9.0, 6.0]]) * ARCSEC
    return xr.Dataset(
        {"circle_rms_mm": ("joint", [0.030, 0.031, 0.032]),
         "circle_radius_mm": ("joint", [200.0, 500.0, 300.0]),
         "error_validation_rms_rad": (("joint", "form"), val),
         "backlash_rad": ("joint", np.array([40.0, 70.0, 50.0]) * ARCSEC),
         "base_compliance_rad_per_Nm": 2.0e-7, "base_fit_r2": 0.9,
         "compliance_rad_per_Nm": ("joint", [1e-6, 2.5e-6, 3e-6])},
        coords={"joint": joints, "form": forms}, attrs={"gravity_model": gravity})


ACC = pd.DataFrame({"n_points": [600, 600, 600], "mean_mm": [1.3, 0.38, 0.038],
                    "rms_mm": [1.5, 0.5, 0.05], "p95_mm": [2.4, 0.74, 0.07],
                    "max_mm": [3.8, 1.2, 0.1]},
                   index=pd.Index(["nominal", "geometric", "full"], name="model"))


def test_findings_from_a_planted_model():
    """By hand: the combined form is smallest for joints 1 and 2 (6 < 8, 10; 7 < 9, 12), not
    3 (5 < 6); its held-out RMS 6–7 arcsec; backlash 40–70 arcsec; base 200 nrad/(N m) is
    8 % of joint 2's 2.5 µrad/(N m); RMS 1.5 → 0.5 (×3) → 0.05 mm (×30)."""
    f = calibration_findings(_model(), ACC).values()
    assert f["circle_rms_um"] == pytest.approx([30.0, 31.0, 32.0])
    assert f["circle_radius_mm_range"] == [200.0, 500.0]
    assert (f["n_joints"], f["combined_form_best_joints"]) == (3, 2)
    assert f["heldout_rms_arcsec_range"] == pytest.approx([6.0, 7.0])
    assert f["backlash_arcsec_range"] == pytest.approx([40.0, 70.0])
    assert f["base_compliance_nrad_per_Nm"] == pytest.approx(200.0)
    assert f["base_share_of_joint2_pct"] == pytest.approx(8.0)
    assert f["improvement_geometric"] == pytest.approx(3.0)
    assert f["improvement_full"] == pytest.approx(30.0)
    assert (f["n_points"], f["nominal_max_mm"], f["full_p95_mm"]) == (600, 3.8, 0.07)


def test_without_a_mass_model_no_base_numbers_and_the_chapter_says_why():
    f = calibration_findings(_model("none: the cell file has no mass_model"), ACC)
    assert f.values()["has_gravity_model"] is False
    assert "base_share_of_joint2_pct" not in f
    text = Prose(load_templates("ch1"), f)("base", ref_base_deflection="[F]",
                                           ref_compliance="[T]")
    assert text.startswith("**No gravity model.** none: the cell file has no mass_model")


def test_chapter_1_prose_follows_its_findings():
    say = Prose(load_templates("ch1"), calibration_findings(_model(), ACC))
    refs = {k: "[R]" for k in ("ref_validation", "ref_base_deflection", "ref_compliance",
                               "ref_accuracy_histograms", "ref_accuracy", "ref_regions")}
    text = " ".join(say("circles", "regression", "base", "base_share", "accuracy",
                        **refs).split())
    assert "30.0, 31.0, 32.0 µm" in text and "best for 2 of 3 joints" in text
    assert "6.0–7.0 arcsec" in text and "40–70 arcsec" in text
    assert "200 nrad per N·m" in text and "That is 8 %" in text
    assert "RMS 1.50, max 3.80 mm" in text and "(×3.0)" in text and "×30 in RMS" in text
    assert "not compared" in Prose(load_templates("ch1"), Findings("calibration"))("against")


def test_a_rigid_joint_2_gives_no_share_and_no_error():
    m = _model()
    m["compliance_rad_per_Nm"] = ("joint", [1e-6, 0.0, 3e-6])
    f = calibration_findings(m, ACC).values()
    assert f["base_share_of_joint2_pct"] is None and f["base_compliance_nrad_per_Nm"] == 200.0
    say = Prose(load_templates("ch1"), calibration_findings(m, ACC))
    text = say("base", "base_share", ref_base_deflection="[F]", ref_compliance="[T]")
    assert "200 nrad per N·m" in text and "No gravity model" not in text and "%" not in text


def test_forms_and_held_out_steps():
    """Three forms planted; the held-out step count comes from the configuration, absent
    when not given."""
    f = calibration_findings(_model(), ACC, holdout_every=5)
    assert (f.values()["n_forms"], f.values()["holdout_every"]) == (3, 5)
    assert f.items["holdout_every"].config_key == "calibration.error_model.holdout_every"
    two = _model().sel(form=["polynomial", "fourier+polynomial"])
    g = calibration_findings(two, ACC).values()
    assert g["n_forms"] == 2 and "holdout_every" not in g


def test_chapter_1_intro_sentences_follow_altered_findings():
    f = calibration_findings(_model(), ACC, holdout_every=5)
    f.items["n_forms"].value = 7
    say = Prose(load_templates("ch1"), f)
    text = " ".join(say("errors_intro", ref_joint_errors="[F6]").split())
    assert "one step in 5" in text and "7 candidate forms" in text
    del f.items["holdout_every"]
    text = " ".join(say("errors_intro", ref_joint_errors="[F6]").split())
    assert "on held-out steps," in text and "7 candidate forms" in text
    text = " ".join(say("circle_intro", "vector_intro", circle_joint=3, turn_deg=45.0,
                        ref_joint_circle="[F4]", ref_vector_model="[F5]",
                        ref_a_prime="[T]").split())
    assert "targets of joint 3" in text and "turned by 45°" in text
