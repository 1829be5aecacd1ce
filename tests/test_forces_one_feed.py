"""A force study whose design cannot identify the cutting coefficients (issue 28: the planned
next run's cuts share one feed per tooth): the gather writes every table with NaN coefficients
and the reason, the findings and chapter 3.1's sentences say why, the workflow's design check
and the planner read the same reason."""

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from robomill.experiment import Cut
from robomill.forces import COEFFICIENT_UNITS, FLAG_COLUMNS, forces_findings, gather_force_study
from robomill.forces.coefficients import (
    IDENTIFIED_COLUMNS,
    design_not_identified,
    identification_status,
    not_identified_reason,
)
from robomill.pipeline.prose import Prose, load_templates
from robomill.plan.measured import Measured, missing_predictions

# five slots at 10 mm/s, 30 000 rpm, 2 flutes: c = 10 µm each; depths 0.5 … 0.1 mm
DEPTHS_MM = [0.5, 0.4, 0.3, 0.2, 0.1]
C_MM = 0.01
# planted mean forces in the cut frame (feed, cross-feed, axial) [N], written by hand
MEANS_N = [(-3.0, 9.0, 1.5), (-2.4, 7.2, 1.2), (-1.8, 5.4, 0.9), (-1.2, 3.6, 0.6),
           (-0.6, 1.8, 0.3)]


def _cut(i: int, depth_mm: float, mean_N, c_mm: float = C_MM) -> xr.Dataset:
    """One cut's dataset as force_cut_dataset writes it (zero spectra, planted means)."""
    scalars = {n: ((), 40.0 + i, {"units": "Hz", "long_name": n})
               for n in ("dominant_hz", "dominant_power", "kinematic_per_mm",
                         "kinematic_power")}
    zeros = {n: (d, np.zeros((3,) * len(d))) for n, d in (
        ("psd", ("axis", "frequency")), ("power_low", ("axis", "lf_bin")),
        ("f_low", ("lf_bin",)), ("f_spatial_low", ("lf_bin",)),
        ("envelope_min", ("axis", "block")), ("envelope_max", ("axis", "block")),
        ("envelope_t", ("block",)), ("excerpt", ("axis", "sample")),
        ("excerpt_t", ("sample",)), ("harmonic_power", ("axis", "harmonic")))}
    return xr.Dataset(
        {"mean_force_cut": ("component", np.asarray(mean_N, float)),
         "mean_force": ("axis", np.asarray(mean_N, float)), **scalars, **zeros,
         "harmonic_hz": ("harmonic", 1000.0 * np.arange(1.0, 4.0))},
        coords={"axis": ["Fx", "Fy", "Fz"], "component": ["feed", "cross_feed", "axial"],
                "frequency": np.arange(3.0), "harmonic": [1, 2, 3]},
        attrs={"cut": f"plan_{i + 1:02d}", "direction": "px", "feed_mm_s": 10.0,
               "depth_mm": depth_mm, "feed_per_tooth_mm": c_mm, "n_samples": 10,
               "tooth_passing_hz": 1000.0})


def _gather(feeds=None):
    feeds = feeds or [C_MM] * len(DEPTHS_MM)
    datasets = [_cut(i, a, f, c) for i, (a, f, c)
                in enumerate(zip(DEPTHS_MM, MEANS_N, feeds, strict=True))]
    processes = {d.attrs["cut"]: {"spindle_rpm": 30000.0, "flutes": 2, "milling": "slot",
                                  "radial_immersion": 1.0} for d in datasets}
    return gather_force_study(datasets, flutes=2, processes=processes)


@pytest.mark.parametrize(("feeds", "code"), [
    ([0.01] * 5, "one_feed_per_tooth"), ([0.01, 0.02], "few_cuts"), ([0.01], "few_cuts"),
    ([0.01, 0.01, 0.02], None), ([0.01 * (1 + 1e-15)] + [0.01] * 3, "one_feed_per_tooth")])
def test_the_reason_follows_the_feeds_per_tooth(feeds, code):
    assert not_identified_reason(feeds) == code


def test_gather_of_one_feed_per_tooth_writes_every_table_and_nan_coefficients():
    """The five planned cuts: spectra, peaks, means and harmonics as always; the coefficient
    table keeps its rows and columns, NaN value/interval, identified False with the reason,
    and the model force is NaN."""
    spectra, peaks, means, harmonics, coeffs = _gather()
    assert list(peaks["cut"]) == [f"plan_{i:02d}" for i in range(1, 6)]
    assert list(peaks["dominant_hz"]) == [40.0, 41.0, 42.0, 43.0, 44.0]
    np.testing.assert_allclose(means[["F_feed_N", "F_cross_feed_N", "F_axial_N"]], MEANS_N)
    assert list(means["depth_mm"]) == DEPTHS_MM
    assert len(harmonics) == 15 and list(harmonics["f_hz"][:3]) == [1000.0, 2000.0, 3000.0]
    assert list(coeffs["name"]) == list(COEFFICIENT_UNITS)
    assert list(coeffs.columns) == ["name", "value", "ci_low", "ci_high", "unit",
                                    *FLAG_COLUMNS, *IDENTIFIED_COLUMNS]
    assert coeffs[["value", "ci_low", "ci_high"]].isna().all().all()
    assert not coeffs["identified"].any() and not coeffs["physical"].any()
    assert set(coeffs["not_identified_reason"]) == {"one_feed_per_tooth"}
    assert identification_status(coeffs) == "one_feed_per_tooth"
    assert np.isnan(spectra["model_force"].values).all()
    assert spectra["model_force"].shape == (721, 3)


def test_gather_of_two_feeds_per_tooth_stays_identified():
    """The same cuts at two feeds per tooth: no reason column, finite coefficients."""
    _, _, _, _, coeffs = _gather([0.01, 0.02, 0.01, 0.02, 0.01])
    assert not set(IDENTIFIED_COLUMNS) & set(coeffs.columns)
    assert np.isfinite(coeffs["value"]).all() and identification_status(coeffs) is None


def test_findings_and_chapter_3_1_say_why_not_identified():
    """The findings carry the reason in code and words; the chapter's coefficient, model
    and chatter sentences say it, none fills a NaN."""
    spectra, peaks, means, _, coeffs = _gather()
    found = forces_findings(peaks, None, mode_match_hz=3.0, band_hz=(15.0, 250.0),
                            prominence_db=12.0, means=means, coefficients=coeffs,
                            planted={"Ktc": 800.0}, settings={"confidence": 0.95})
    v = found.values()
    assert v["coefficients_not_identified_reason"] == "one_feed_per_tooth"
    assert v["coefficients_not_identified"] == (
        "not identified: the cuts have one feed per tooth (need ≥ 3 cuts at ≥ 2 feeds per "
        "tooth)")
    assert "coefficient_Ktc" not in v and "planted_error_pct_max" not in v
    assert v["coefficient_flags_checked"] is False and v["n_coefficients"] == 6
    assert v["F_feed_N_range"] == [-3.0, -0.6]  # the levels are still there
    say = Prose(load_templates("ch3_forces"), found)
    text = " ".join(say("model", "coefficients", "planted", "physical", "physical_ok", "uses",
                        shape="slot", ref_model_force_shape="", ref_coefficients="").split())
    assert "Cutting coefficients Ktc … Kae: **not identified: the cuts have one feed per tooth" \
        in text
    assert "force shape (eq. 3.1) is not drawn: it needs the cutting coefficients, not " \
        "identified" in text
    assert "stability lobes need the coefficients" in text
    assert "nan" not in text.lower() and "{" not in text and "Ktc =" not in text
    # another reason, the same sentences
    found.items["coefficients_not_identified"].value = "not identified: fewer than 3 force cuts"
    again = Prose(load_templates("ch3_forces"), found)("coefficients")
    assert "**not identified: fewer than 3 force cuts**" in again


def test_the_design_check_of_the_workflow_and_the_planner_read_the_same_reason():
    """design_not_identified (chapter 4 left out at parse time) from the manifest's cuts; the
    planner treats a NaN table as no coefficients and says why."""
    cuts = [Cut(id=f"plan_{i}", set=None, segment=None, feed_mm_s=10.0, depth_mm=a, direction="px")
            for i, a in enumerate(DEPTHS_MM)]
    exp = {"spindle_rpm": 30000.0, "flutes": 2}
    why = design_not_identified(cuts, exp, [c.id for c in cuts])
    assert why.startswith("not identified: the cuts have one feed per tooth")
    assert design_not_identified(cuts, exp, []) is None
    assert design_not_identified(cuts[:2], exp, ["plan_0", "plan_1"]).startswith(
        "not identified: fewer than 3 force cuts")
    faster = cuts[:2] + [Cut(id="fast", set=None, segment=None, feed_mm_s=20.0, depth_mm=0.3,
                             direction="px")]
    assert design_not_identified(faster, exp, ["plan_0", "plan_1", "fast"]) is None
    coeffs = _gather()[4]
    m = Measured(coefficients=coeffs, modes=pd.DataFrame({"f_n_hz": [50.0]}))
    assert not m.has("coefficients")
    missing = missing_predictions(m)
    assert "one feed per tooth" in missing["force"] and "stability_margin" in missing
    assert Measured(coefficients=_gather([0.01, 0.02] * 2 + [0.03])[4]).has("coefficients")
