"""The chapter 3.1 sentence on the cutting coefficients' sanity flags (issue 21 point 5):
one short clause when all are physical, each non-physical coefficient named with why."""

import pandas as pd

from robomill.forces import FLAG_COLUMNS, coefficient_flag_sentence


def _table(overrides=None):
    rows = [{"name": n, "value": v, "ci_low": v - 1, "ci_high": v + 1, "unit": u,
             "negative": v < 0, "fit_residual_rms_N": 0.5, "fit_signal_rms_N": 10.0,
             "residual_exceeds_signal": False}
            for n, v, u in (("Ktc", 700.0, "N/mm^2"), ("Kte", 20.0, "N/mm"),
                            ("Krc", 200.0, "N/mm^2"), ("Kre", 25.0, "N/mm"),
                            ("Kac", 100.0, "N/mm^2"), ("Kae", 3.0, "N/mm"))]
    table = pd.DataFrame(rows)
    for (name, col), val in (overrides or {}).items():
        table.loc[table["name"] == name, col] = val
    table["negative"] = table["value"] < 0
    table["physical"] = ~(table["negative"] | table["residual_exceeds_signal"].astype(bool))
    return table


def test_all_physical_is_one_short_clause():
    assert coefficient_flag_sentence(_table()) == (
        "All 6 coefficients are physical (positive, resolved by their fit).")


def test_a_negative_coefficient_is_named_with_its_value():
    text = coefficient_flag_sentence(_table({("Kre", "value"): -4.2}))
    assert text.startswith("**Not physical:** Kre is negative (-4.2 N/mm)")
    for other in ("Ktc", "Kte", "Krc", "Kac", "Kae"):
        assert other not in text


def test_an_unresolved_coefficient_names_residual_and_signal():
    table = _table({("Kae", "residual_exceeds_signal"): True,
                      ("Kae", "fit_residual_rms_N"): 3.5, ("Kae", "fit_signal_rms_N"): 1.25,
                      ("Kac", "value"): -1.0})
    text = coefficient_flag_sentence(table)
    assert ("Kae is not resolved: its fit leaves 3.5 N rms of residual against 1.25 N rms of "
            "signal") in text
    assert "Kac is negative (-1 N/mm^2)" in text
    assert text.count(";") == 1 and text.endswith(".")


def test_a_table_without_flags_says_nothing():
    table = _table().drop(columns=list(FLAG_COLUMNS))
    assert coefficient_flag_sentence(table) == ""
