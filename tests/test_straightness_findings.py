"""Chapter 3.2's findings (robomill.straightness.findings) from planted runs and peaks, and
the chapter's sentences following them (notebooks/templates/ch3_2.yaml)."""

import numpy as np
import pandas as pd
import pytest
import xarray as xr

from robomill.findings import Findings
from robomill.pipeline.prose import Prose, load_templates
from robomill.straightness.findings import quiet_band, straightness_findings

KW = dict(surface_band_per_mm=(7.0, 9.0), fmax_store_per_mm=20.0, threshold=25.0)


def _profiles(line_at_8=True):
    """Two runs, +Y at 2 and 10 mm/s: a flat floor of 1 µm², run a with a 400 µm² line at
    8 mm⁻¹ (inside the surface band) when ``line_at_8``."""
    f = np.arange(0.0, 20.0 + 1e-9, 0.01)
    power = np.ones((2, f.size))
    if line_at_8:
        power[0, np.argmin(np.abs(f - 8.0))] = 400.0
    return xr.Dataset({"power_um2": (("run", "f"), power)},
                      coords={"run": ["a", "b"], "f": f, "direction": ("run", ["py", "py"]),
                              "feed_mm_s": ("run", [2.0, 10.0])})


def _peaks(line_at_8=True):
    rows = [("py", 2.0, 0.50, 1.0, 2.0, "gear"), ("py", 2.0, 0.45, 0.9, 0.5, "gear"),
            ("py", 10.0, 0.45, 4.5, 3.0, "gear"),
            ("py", 2.0, 6.5, 13.0, 1.5, "temporal"), ("py", 10.0, 1.3, 13.0, 1.7, "temporal")]
    if line_at_8:
        rows.append(("py", 2.0, 8.0, 16.0, 28.0, "unclassified"))
    out = pd.DataFrame(rows, columns=["direction", "feed_mm_s", "f_spatial_per_mm",
                                      "f_temporal_hz", "amplitude_um", "mechanism"])
    return out.assign(run=np.where(out["feed_mm_s"] == 2.0, "a", "b"))


def test_findings_from_planted_runs():
    """By hand: gear peaks 0.45–0.50 mm⁻¹; the largest gear peak of each run at 0.50 (run a,
    2 µm) and 0.45 mm⁻¹ (run b): wavelengths 2.0 and 2.22 mm; two temporal peaks at 13 Hz
    (wavelengths 1/6.5 and 1/1.3 mm); one peak in the 7–9 mm⁻¹ band: the motion has a
    component there; the quiet band is 18–20 mm⁻¹."""
    f = straightness_findings(_profiles(), _peaks(), **KW).values()
    assert (f["n_runs"], f["feeds_mm_s"]) == (2, [2.0, 10.0])
    assert f["n_gear_peaks"] == 3 and f["gear_f_range_per_mm"] == [0.45, 0.5]
    assert f["gear_main_wavelength_mm_range"] == pytest.approx([2.0, 1 / 0.45])
    assert (f["n_temporal"], f["temporal_hz_mean"], f["temporal_hz_std"]) == (2, 13.0, 0.0)
    assert f["temporal_wavelength_mm_range"] == pytest.approx([1 / 6.5, 1 / 1.3])
    assert f["quiet_band_per_mm"] == [18.0, 20.0] == list(quiet_band((7.0, 9.0), 20.0))
    assert f["n_surface_band_peaks"] == 1 and f["verdict_motion_in_surface_band"] == "peaks"
    assert f["threshold_motion_in_surface_band"] == 25.0
    assert f["surface_band_peak_to_floor_max"] == pytest.approx(400.0)
    assert f["quiet_band_peak_to_floor_range"] == pytest.approx([1.0, 1.0])


def test_a_quiet_surface_band_gives_the_verdict_none():
    f = straightness_findings(_profiles(False), _peaks(False), **KW).values()
    assert f["n_surface_band_peaks"] == 0 and f["verdict_motion_in_surface_band"] == "none"


def test_chapter_3_2_prose_follows_its_findings():
    say = Prose(load_templates("ch3_2"), straightness_findings(_profiles(), _peaks(), **KW))
    text = " ".join(say("gear_peaks", "surface_band", "surface_band_verdict", "temporal",
                        ref_band_floor="[T]").split())
    assert "3 peaks are attributed to a gear element" in text
    assert "between 0.450 and 0.500 mm⁻¹" in text and "2.00–2.22 mm" in text
    assert "the 2 runs have 1 peak(s)" in text and "400.0× the noise floor" in text
    assert "needs 25× its band median" in text and "has components there" in text
    assert "13.00 ± 0.00 Hz" in text
    quiet = Prose(load_templates("ch3_2"), straightness_findings(_profiles(False),
                                                                 _peaks(False), **KW))
    assert "no component there" in quiet("surface_band_verdict")
    none = Prose(load_templates("ch3_2"), Findings("straightness"))
    assert "No peak is attributed" in none("gear_peaks") and "not compared" in none("against")
