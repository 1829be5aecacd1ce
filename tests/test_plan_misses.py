"""Why an out-of-sample prediction missed (robomill.plan.misses): only out-of-sample misses are
explained, each from the evidence in the run's files."""

import pandas as pd

from robomill.plan.misses import explain_misses


def _row(cut, qty, pred, low, high, out, held, in_sample=False):
    return {"cut": cut, "quantity": qty, "unit": "", "predicted": pred, "low": low,
            "high": high, "outcome": out, "held": held, "in_sample": in_sample}


CHECK = pd.DataFrame([
    _row("p1", "force", 1.5, 1.0, 2.0, 1.6, True),
    _row("p1", "deflection_normal", 0.5, 0.3, 0.8, 1.5, False),      # force held: compliance
    _row("p2", "force", 1.5, 1.0, 2.0, 3.0, False),                  # extrapolated, no chatter
    _row("p2", "deflection_axial", 0.5, 0.3, 0.8, 1.2, False),       # follows the force
    _row("p3", "stability", 1.0, 0.5, 1.5, 0.0, False),              # chattered above the band
    _row("p4", "waviness", 1.0, 0.5, 1.5, 1.2, True),
    _row("s1", "force", 6.0, 5.0, 7.0, 9.0, False, in_sample=True),  # in-sample: not explained
])
PLAN = pd.DataFrame({"cut": ["p1", "p2", "p3", "p4"],
                     "extrapolation": [False, True, False, False],
                     "extrapolation_reason": ["", "feed per tooth", "", ""],
                     "interval_widening": [1.0, 2.4, 1.0, 1.0]})
VERDICTS = pd.DataFrame({"cut": ["p1", "p2", "p3", "p3"],
                         "verdict": ["stable", "stable", "stable", "chatter"],
                         "chatter_hz": [None, None, None, 1015.0]})


def test_each_out_of_sample_miss_with_its_evidence():
    m = explain_misses(CHECK, PLAN, VERDICTS, (10.0, 100.0)).set_index(["cut", "quantity"])
    assert sorted(m.index) == [("p1", "deflection_normal"), ("p2", "deflection_axial"),
                               ("p2", "force"), ("p3", "stability")]
    d = m.loc[("p1", "deflection_normal")]
    assert d["causes"] == "compliance" and d["beyond"] == "above"
    assert d["ratio"] == 3.0 and "3× the model's" in d["explanation"]
    assert "normal to the wall" in d["explanation"]
    f = m.loc[("p2", "force")]
    assert f["causes"] == "extrapolated;model"
    assert "feed per tooth" in f["explanation"] and "2.4×" in f["explanation"]
    assert m.loc[("p2", "deflection_axial"), "causes"] == "extrapolated;force"
    s = m.loc[("p3", "stability")]
    assert s["causes"] == "chatter" and s["beyond"] == "chatter"
    assert "1015 Hz, above the 10–100 Hz" in s["explanation"]


def test_no_misses_no_rows_and_no_band_no_band_claim():
    assert explain_misses(CHECK[CHECK["held"] | CHECK["in_sample"]]).empty
    s = explain_misses(CHECK, PLAN, VERDICTS, None).set_index("cut").loc["p3"]
    assert s["explanation"] == "The cut chattered at 1015 Hz."
