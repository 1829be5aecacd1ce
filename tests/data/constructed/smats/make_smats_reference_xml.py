"""Regenerate ``nist_layout_reference.xml``: a profile in the SMATS XML layout with the header
fields written as NIST writes them and the file's own reference parameters, constructed.

No public SMATS XML file was found (``tests/data/real/smats/SOURCE.md``). This file follows
what a NIST export carries beyond ``milled_profile.xml``: lengths with their unit
(``<SPACING>0.5 um</SPACING>``, ``<UNITS>micrometers</UNITS>``), a unit-bearing calibration
constant (``<KCAL>1.0000 um/um</KCAL>``) and the sections ``ROUGHNESS_SURFACE_PARAMETERS``,
``WAVINESS_SURFACE_PARAMETERS`` (with the filter settings) and
``PRIMARY_SURFACE_PARAMETERS``.

The profile (µm; 8000 points every 0.5 µm, 4 mm): a waviness cosine of amplitude
``A_W = 2 µm`` and wavelength 2 mm, a roughness cosine of ``A_R = 0.4 µm`` and 0.025 mm, a
tilt of 0.8 µm/mm and an offset of 5 µm. The reference values are written from the
planted components, not from any filter: the ISO 16610-21 Gaussian mean line at
λc = 0.25 mm transmits a cosine of wavelength λ with amplitude
``T(λ) = exp(−π (α λc / λ)²)``, α = sqrt(ln 2 / π), so the waviness profile is
``T(2)·A_W cos`` and the roughness profile ``A_R cos(…0.025) + (1 − T(2))·A_W cos(…2)``
(T(0.025) ≈ 1e-30). Then (whole periods) Wq = T·A_W/√2, Wa = 2·T·A_W/π, Wt = 2·T·A_W;
Rq = sqrt(A_R²/2 + ((1 − T)·A_W)²/2); Pq = sqrt(A_W²/2 + A_R²/2). Pa, Psk and Pku of the
roughness section are the moments of the planted roughness profile evaluated on the grid.

Run ``python make_smats_reference_xml.py`` in this folder to rewrite the file.
"""

from pathlib import Path

import numpy as np

N = 8000
SPACING_UM = 0.5
A_W, LAMBDA_W = 2.0, 2.0
A_R, LAMBDA_R = 0.4, 0.025
LAMBDA_C = 0.25
ALPHA = np.sqrt(np.log(2) / np.pi)
T_W = float(np.exp(-np.pi * (ALPHA * LAMBDA_C / LAMBDA_W) ** 2))
X_MM = np.arange(N) * SPACING_UM * 1e-3
ROUGH = A_R * np.cos(2 * np.pi * X_MM / LAMBDA_R) + (1 - T_W) * A_W * np.cos(
    2 * np.pi * X_MM / LAMBDA_W)
RQ = float(np.sqrt(A_R**2 / 2 + ((1 - T_W) * A_W) ** 2 / 2))
REFERENCE = {
    "roughness": {"PA": float(np.mean(np.abs(ROUGH))), "PQ": RQ,
                  "PSK": float(np.mean(ROUGH**3) / RQ**3),
                  "PKU": float(np.mean(ROUGH**4) / RQ**4)},
    "waviness": {"PA": 2 * T_W * A_W / np.pi, "PQ": T_W * A_W / np.sqrt(2),
                 "PT": 2 * T_W * A_W},
    "primary": {"PQ": float(np.sqrt(A_W**2 / 2 + A_R**2 / 2))},
}


def heights_um() -> np.ndarray:
    return (5.0 + 0.8 * X_MM + A_W * np.cos(2 * np.pi * X_MM / LAMBDA_W)
            + A_R * np.cos(2 * np.pi * X_MM / LAMBDA_R))


def _section(tag: str, values: dict, filt: bool) -> str:
    lines = [f"    <{tag}>"]
    if filt:
        lines += ["      <FILTER>Gaussian</FILTER>", f"      <CUTOFF>{LAMBDA_C} mm</CUTOFF>"]
    for k, v in values.items():
        unit = "" if k in ("PSK", "PKU") else " um"
        lines.append(f"      <{k}>{v:.6f}{unit}</{k}>")
    return "\n".join(lines + [f"    </{tag}>"])


def text() -> str:
    values = "\n".join(f"{v:.5f}" for v in heights_um())
    sections = "\n".join([
        _section("PRIMARY_SURFACE_PARAMETERS", REFERENCE["primary"], False),
        _section("ROUGHNESS_SURFACE_PARAMETERS", REFERENCE["roughness"], True),
        _section("WAVINESS_SURFACE_PARAMETERS", REFERENCE["waviness"], True)])
    return f"""<?xml version="1.0" encoding="UTF-8"?>
<DATA>
  <PART>RM-constructed-002</PART>
  <PROCESS>end milled (constructed profile)</PROCESS>
  <MEASUREMENT>stylus profile, 4 mm</MEASUREMENT>
  <DATAFILE>
    <FILENAME>milled_reference.smd</FILENAME>
    <UNITS>micrometers</UNITS>
    <NUMPOINTS>{N}</NUMPOINTS>
    <SPACING>{SPACING_UM} um</SPACING>
    <KCAL>1.0000 um/um</KCAL>
    <DATA_TYPE>2D</DATA_TYPE>
{sections}
    <DATA_POINT_VALUES>
{values}
    </DATA_POINT_VALUES>
  </DATAFILE>
</DATA>
"""


if __name__ == "__main__":
    Path(__file__).with_name("nist_layout_reference.xml").write_text(text())
