"""Impact-test files: hammer + accelerometer hits (CSV) and FRFs in UFF 58 (``pyuff``).

``impact/hit<X|Y|Z>_<k>.csv`` (``docs/data-contract.md``): columns ``t_s, force_N, ax_ms2,
ay_ms2, az_ms2``; uniform, strictly increasing time; at least 64 rows.

UFF 58 ("function at nodal DOF", the format modal test software exports): one ASCII/binary
data set per FRF (function type 4, receptance: ordinate displacement over force) and per
coherence (type 6), with the response and reference directions as DOF codes (X=1, Y=2,
Z=3 at node 1). :func:`write_frf_uff` and :func:`read_frf_uff` round-trip an FRF dataset
(``H``, ``coherence`` over ``output, input, frequency``); a broken file raises
:class:`RawDataError`.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import xarray as xr

from robomill.io.errors import RawDataError
from robomill.io.tables import check_uniform, read_numeric_csv

COLUMNS = ("t_s", "force_N", "ax_ms2", "ay_ms2", "az_ms2")
DOF_CODE = {"X": 1, "Y": 2, "Z": 3}
"""UFF direction codes of the base axes."""
MIN_ROWS = 64


def read_hit(path: str | Path, *, fs_hz: float | None = None) -> tuple[float, np.ndarray,
                                                                        np.ndarray]:
    """Read one hit: ``(fs_hz, force_N (n,), accel_ms2 (n, 3))``.

    Raises
    ------
    RawDataError
        Missing/mis-named columns, text or NaN in a field, a truncated row, fewer than 64
        rows, or a time column that is not uniform and strictly increasing (or whose
        spacing disagrees with ``fs_hz`` when given).
    """
    df = read_numeric_csv(path, COLUMNS, min_rows=MIN_ROWS)
    t = df["t_s"].to_numpy()
    dt = check_uniform(path, t, "t_s", step=None if fs_hz is None else 1.0 / fs_hz)
    return 1.0 / dt, df["force_N"].to_numpy(), df[["ax_ms2", "ay_ms2", "az_ms2"]].to_numpy()


def write_frf_uff(ds: xr.Dataset, path: str | Path) -> Path:
    """Write ``H`` (complex, m/N) and ``coherence`` of an FRF dataset as UFF 58 sets.

    Frequency lines must be uniform; the DC line is written as 0 where it is NaN.
    """
    import pyuff

    from robomill.io.atomic import atomic_path

    f = ds["frequency"].values
    df = float(f[1] - f[0])
    sets = []
    for o in ds["output"].values:
        for i in ds["input"].values:
            h = np.nan_to_num(ds["H"].sel(output=o, input=i).values)
            coh = np.nan_to_num(ds["coherence"].sel(output=o, input=i).values)
            common = dict(rsp_node=1, rsp_dir=DOF_CODE[str(o)], ref_node=1,
                          ref_dir=DOF_CODE[str(i)], abscissa_spacing=1, abscissa_min=float(f[0]),
                          abscissa_inc=df, abscissa_spec_data_type=18, x=f, id2="robomill",
                          id3="", id4="", id5="", rsp_ent_name="tooltip", ref_ent_name="tooltip")
            sets.append(pyuff.prepare_58(func_type=4, id1=f"H {o}/{i} receptance m/N",
                                         ordinate_spec_data_type=8,
                                         orddenom_spec_data_type=13, data=h.astype(complex),
                                         **common))
            sets.append(pyuff.prepare_58(func_type=6, id1=f"coherence {o}/{i}",
                                         ordinate_spec_data_type=0,
                                         orddenom_spec_data_type=0, data=coh.astype(float),
                                         **common))
    with atomic_path(path) as tmp:
        pyuff.UFF(str(tmp)).write_sets(sets, mode="overwrite")
    return Path(path)


def read_frf_uff(path: str | Path) -> xr.Dataset:
    """Read UFF 58 FRFs (type 4) and coherences (type 6) into ``H`` and ``coherence`` over
    ``output, input, frequency``.

    Raises
    ------
    RawDataError
        If the file is missing or not valid UFF, holds no type-58 FRF, the FRFs disagree in
        frequency axis, or a direction code is not 1, 2 or 3.
    """
    import pyuff

    from robomill.modal import frf_coords

    path = Path(path)
    if not path.exists():
        raise RawDataError(path, "file does not exist")
    try:
        sets = pyuff.UFF(str(path)).read_sets()
    except Exception as exc:  # pyuff raises bare Exception on malformed files
        raise RawDataError(path, f"not a readable universal file ({exc})",
                           expected="UFF data sets of type 58 (ASCII or binary)") from None
    if isinstance(sets, dict):
        sets = [sets]
    sets = [s for s in sets if isinstance(s, dict) and s.get("type") in (58, "58")]
    frfs = [s for s in sets if int(s.get("func_type", 0)) == 4]
    if not frfs:
        raise RawDataError(path, "no FRF data set (UFF 58 with function type 4)",
                           expected="nine FRFs (X, Y, Z responses × X, Y, Z references)")
    code = {v: k for k, v in DOF_CODE.items()}
    f = np.asarray(frfs[0]["x"], float)
    H = np.full((3, 3, f.size), np.nan + 0j)
    coh = np.full((3, 3, f.size), np.nan)
    for n, s in enumerate(sets):
        where = f"data set {n + 1} ({s.get('id1', '').strip()})"
        try:
            o, i = code[abs(int(s["rsp_dir"]))], code[abs(int(s["ref_dir"]))]
        except (KeyError, ValueError, TypeError):
            raise RawDataError(path, f"direction codes {s.get('rsp_dir')!r}/"
                               f"{s.get('ref_dir')!r}", where=where,
                               expected="rsp_dir and ref_dir in 1, 2, 3 (X, Y, Z)") from None
        x = np.asarray(s.get("x", []), float)
        data = np.asarray(s.get("data", []))
        if x.shape != f.shape or not np.allclose(x, f) or data.shape != f.shape:
            raise RawDataError(path, f"{data.size} points on a different frequency axis",
                               where=where, expected=f"{f.size} points from {f[0]:g} Hz "
                                                     f"every {f[1] - f[0]:g} Hz")
        oi, ii = "XYZ".index(o), "XYZ".index(i)
        if int(s["func_type"]) == 4:
            H[oi, ii] = data
        elif int(s["func_type"]) == 6:
            coh[oi, ii] = np.real(data)
    missing = [f"{o}/{i}" for a, o in enumerate("XYZ") for b, i in enumerate("XYZ")
               if not np.isfinite(H[a, b, 1:]).any()]
    if missing:
        raise RawDataError(path, f"no FRF for response/reference {', '.join(missing)} "
                           "(truncated or incomplete file?)",
                           expected="nine FRFs (X, Y, Z responses × X, Y, Z references)")
    if f[0] == 0:
        H[..., 0] = np.nan
    return xr.Dataset(
        {"H": (("output", "input", "frequency"), H,
               {"units": "m/N", "long_name": "receptance FRF"}),
         "coherence": (("output", "input", "frequency"), coh,
                       {"units": "1", "long_name": "ordinary coherence"})},
        coords=frf_coords(f))


def read_frf(path: str | Path) -> xr.Dataset:
    """Open ``results/modal/frf.nc`` with its complex variables (``H``, ``H2``) restored."""
    from robomill.io.artefacts import open_artefact
    from robomill.modal import join_complex

    return join_complex(open_artefact(path))
