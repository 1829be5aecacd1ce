"""Chapter 1's tables, from the calibration model (``results/calibration/model.nc``): pure
functions of the dataset :mod:`robomill.calibration.dataset` writes; the chapter only
displays what they return (the accuracy tables: :mod:`robomill.calibration.accuracy`)."""

from __future__ import annotations

import numpy as np
import pandas as pd
import xarray as xr

ARCSEC_RAD = np.pi / 180 / 3600


def a_prime_table(model: xr.Dataset) -> pd.DataFrame:
    """The identified vectors a'_i (``a_prime_mm(joint, xyz)``, eq. 1.4) and their lengths
    ``|a'| [mm]``."""
    a = model["a_prime_mm"].to_pandas()
    a["|a'| [mm]"] = np.linalg.norm(a.to_numpy(), axis=1)
    return a


def validation_table(model: xr.Dataset) -> pd.DataFrame:
    """Held-out RMS [arcsec] of the regression forms per joint
    (``error_validation_rms_rad(joint, form)``), the chosen polynomial degree and the backlash
    [arcsec] (``backlash_rad``)."""
    val = model["error_validation_rms_rad"].to_pandas() / ARCSEC_RAD
    val["chosen degree"] = model["error_degree"].values
    val["backlash [arcsec]"] = model["backlash_rad"].values / ARCSEC_RAD
    return val


def compliance_table(model: xr.Dataset) -> pd.DataFrame:
    """The joint compliances from the load discs [µrad/(N·m)] (``compliance_rad_per_Nm``),
    whether each was identifiable and the gravity torque at home [N·m]."""
    return pd.DataFrame({
        "compliance [µrad/(N·m)]": model["compliance_rad_per_Nm"].values * 1e6,
        "identifiable": model["compliance_identifiable"].values.astype(bool),
        "torque at home [N·m]": model["tau_home_Nm"].values,
    }, index=pd.Index(model["joint"].values, name="joint"))
