"""The cutting coefficients' sanity flags (tests assert on the
flag values, not on the English sentence chapter 3.1 makes of them): a negative coefficient
and one whose fit leaves more residual than signal are flagged, the others are physical."""

import numpy as np
import pandas as pd

from robomill.forces import FLAG_COLUMNS, coefficient_flags

NAMES = ("Ktc", "Kte", "Krc", "Kre", "Kac", "Kae")


def _table(values):
    return pd.DataFrame({"name": NAMES, "value": values, "ci_low": np.subtract(values, 1),
                         "ci_high": np.add(values, 1), "unit": ["N/mm^2", "N/mm"] * 3})


def test_all_positive_and_resolved_are_physical():
    out = coefficient_flags(_table([700.0, 20.0, 200.0, 25.0, 100.0, 3.0]),
                            {n: (0.5, 10.0) for n in NAMES})
    assert set(FLAG_COLUMNS) <= set(out.columns)
    assert out["physical"].all() and not out["negative"].any()
    assert not out["residual_exceeds_signal"].any()


def test_a_negative_and_an_unresolved_coefficient_are_flagged_alone():
    fit = {n: (0.5, 10.0) for n in NAMES} | {"Kae": (3.5, 1.25)}
    out = coefficient_flags(_table([700.0, 20.0, 200.0, -4.2, 100.0, 3.0]), fit).set_index("name")
    assert out.loc["Kre", "negative"] and not out.loc["Kre", "residual_exceeds_signal"]
    assert out.loc["Kae", "residual_exceeds_signal"] and not out.loc["Kae", "negative"]
    assert (out.loc["Kae", "fit_residual_rms_N"], out.loc["Kae", "fit_signal_rms_N"]) == (3.5,
                                                                                         1.25)
    assert out["physical"].to_dict() == {"Ktc": True, "Kte": True, "Krc": True, "Kre": False,
                                         "Kac": True, "Kae": False}


def test_residual_equal_to_signal_is_not_flagged():
    """The flag is strict: a residual as large as the signal still counts as resolved."""
    fit = {n: (2.0, 2.0) for n in NAMES}
    out = coefficient_flags(_table([1.0] * 6), fit)
    assert not out["residual_exceeds_signal"].any() and out["physical"].all()
