"""Chapter-1 summaries: improvement ratios and the region table."""

from __future__ import annotations

import pandas as pd
import pytest

from robomill.calibration import improvement_ratios, region_table


def test_improvement_ratios_divide_the_baseline_rms():
    acc = pd.DataFrame({"rms_mm": [2.0, 0.5, 0.1]},
                       index=pd.Index(["nominal", "geometric", "full"], name="model"))
    r = improvement_ratios(acc)
    assert r.tolist() == pytest.approx([1.0, 4.0, 20.0])


def test_region_table_pivots_models_into_columns():
    reg = pd.DataFrame({"region": ["a", "a", "a", "b", "b", "b"],
                        "model": ["full", "nominal", "geometric"] * 2,
                        "rms_mm": [0.1, 2.0, 0.5, 0.2, 3.0, 0.6],
                        "n_points": [10, 10, 10, 7, 7, 7]})
    t = region_table(reg)
    assert t.columns.tolist() == ["nominal", "geometric", "full", "n_points"]
    assert t.loc["b", "nominal"] == 3.0 and t.loc["a", "n_points"] == 10
