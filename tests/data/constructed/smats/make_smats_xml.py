"""Regenerate ``milled_profile.xml``: a profile in the SMATS XML layout, constructed.

No public SMATS XML file with a licence was found (``tests/data/real/smats/SOURCE.md``), so
this file is built from the layout NIST's profiles use: ``<DATA>`` with ``<PART>``,
``<PROCESS>``, ``<MEASUREMENT>`` and one ``<DATAFILE>`` holding ``<FILENAME>``, ``<UNITS>``,
``<NUMPOINTS>``, ``<SPACING>`` (in the unit), ``<KCAL>``, ``<DATA_TYPE>`` and
``<DATA_POINT_VALUES>`` (one height per line).

The profile (µm, 4000 points every 0.25 µm, 1 mm): a 0.8 µm cosine of 0.1 mm wavelength
(10 periods), a 0.12 µm cosine of 0.02 mm (50 periods), a tilt of 0.5 µm/mm and an offset of
3 µm. Whole periods of cosines are orthogonal to a constant and (up to the sampling) to a
line, so once tilt and offset are removed its RMS is Pq = sqrt(0.8²/2 + 0.12²/2)
= 0.572 014 µm (``PQ_UM``).

Run ``python make_smats_xml.py`` in this folder to rewrite the file.
"""

from pathlib import Path

import numpy as np

N = 4000
SPACING_UM = 0.25
AMPLITUDES_UM = (0.8, 0.12)
WAVELENGTHS_MM = (0.1, 0.02)
PQ_UM = float(np.sqrt(sum(a**2 / 2 for a in AMPLITUDES_UM)))


def heights_um() -> np.ndarray:
    x_mm = np.arange(N) * SPACING_UM * 1e-3
    z = 3.0 + 0.5 * x_mm
    for a, lam in zip(AMPLITUDES_UM, WAVELENGTHS_MM, strict=True):
        z = z + a * np.cos(2 * np.pi * x_mm / lam)
    return z


def text() -> str:
    values = "\n".join(f"{v:.5f}" for v in heights_um())
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<DATA>
  <PART>RM-constructed-001</PART>
  <PROCESS>end milled (constructed profile)</PROCESS>
  <MEASUREMENT>stylus profile, 1 mm</MEASUREMENT>
  <DATAFILE>
    <FILENAME>milled_profile.smd</FILENAME>
    <UNITS>um</UNITS>
    <NUMPOINTS>{N}</NUMPOINTS>
    <SPACING>{SPACING_UM}</SPACING>
    <KCAL>1</KCAL>
    <DATA_TYPE>2D</DATA_TYPE>
    <DATA_POINT_VALUES>
{values}
    </DATA_POINT_VALUES>
  </DATAFILE>
</DATA>
"""


if __name__ == "__main__":
    Path(__file__).with_name("milled_profile.xml").write_text(text())
