"""The areal scan file of the data contract: ``areal/<cut>.nc``.

One netCDF4/HDF5 file per scan (written by ``robomill import x3p --areal``, ``robomill import
sdf`` and the other areal formats), self-describing:

* ``z_um (y, x)``: heights [µm], NaN where the instrument measured nothing;
* coordinates ``x`` and ``y`` [mm] (uniform, from 0): the scan's own frame;
* attributes: ``source_file``, ``source_format`` and whatever the instrument's file states
  (``instrument``, ``manufacturer``, ``model``, ``serial``, ``probe``, ``date`` …), kept into
  the chapter's artefacts; ``valid_points`` (the number of measured points).

The cut's feed direction in that frame is the manifest entry's ``feed_angle_deg`` (0: the
feed runs along +x).
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from robomill.errors import RawDataError

WHAT = "an areal scan: netCDF with z_um (y, x) in µm and uniform coordinates x, y in mm"


def write_areal(path: str | Path, z_um: np.ndarray, dx_mm: float, dy_mm: float,
                attrs: Mapping[str, Any]) -> Path:
    """Write a scan in the contract layout (float32 heights, compressed)."""
    import xarray as xr

    z = np.asarray(z_um, float)
    ny, nx = z.shape
    ds = xr.Dataset(
        {"z_um": (("y", "x"), z.astype("float32"),
                  {"units": "um", "long_name": "height (NaN: not measured)"})},
        coords={"x": ("x", np.arange(nx) * float(dx_mm), {"units": "mm"}),
                "y": ("y", np.arange(ny) * float(dy_mm), {"units": "mm"})},
        attrs={**{k: (str(v) if not isinstance(v, (int, float)) else v)
                  for k, v in attrs.items() if v is not None},
               "valid_points": int(np.isfinite(z).sum())})
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    ds.to_netcdf(path, engine="h5netcdf",
                 encoding={"z_um": {"zlib": True, "complevel": 4}})
    return path


def read_areal(path: str | Path) -> tuple[np.ndarray, float, float, dict[str, Any]]:
    """Read a contract scan: ``(z_um (ny, nx), dx_mm, dy_mm, attrs)``.

    Raises
    ------
    RawDataError
        Not readable as netCDF/HDF5; no ``z_um`` of dims ``(y, x)``; fewer than 2 points
        along an axis; a non-uniform or non-increasing coordinate; no valid point.
    """
    import xarray as xr

    path = Path(path)
    try:
        ds = xr.open_dataset(path, engine="h5netcdf")
    except Exception as exc:  # noqa: BLE001 - any reader failure is one line
        raise RawDataError(path, f"not readable as netCDF ({type(exc).__name__}: {exc})",
                           where="file", expected=WHAT) from None
    with ds:
        if "z_um" not in ds or ds["z_um"].dims != ("y", "x"):
            raise RawDataError(path, "no variable z_um with dims (y, x)", where="z_um",
                               expected=WHAT)
        z = ds["z_um"].to_numpy().astype(float)
        spacing = []
        for axis in ("x", "y"):
            c = ds[axis].to_numpy().astype(float)
            if c.size < 2:
                raise RawDataError(path, f"{c.size} point(s) along {axis}", where=axis,
                                   expected="at least 2 points along each axis")
            d = np.diff(c)
            if not (d > 0).all() or np.ptp(d) > 1e-6 * d.mean():
                raise RawDataError(path, f"coordinate {axis} is not uniform and increasing",
                                   where=axis, expected="a uniform grid in mm")
            spacing.append(float(d.mean()))
        attrs = dict(ds.attrs)
    if not np.isfinite(z).any():
        raise RawDataError(path, f"the scan has only invalid points ({z.shape[1]} × "
                           f"{z.shape[0]}, all NaN)", where="z_um",
                           expected="a scan with measured points")
    return z, spacing[0], spacing[1], attrs


def scan_problem(path: str | Path) -> str | None:
    """One line saying why the scan at ``path`` cannot be analysed (:func:`read_areal`'s
    error), or ``None``. Cheap for the files :func:`write_areal` wrote: their
    ``valid_points`` attribute (with the variable's shape) answers without reading the
    heights (the workflow asks for every scan while it builds the DAG)."""
    try:
        import h5py

        with h5py.File(path, "r") as f:
            n = f.attrs.get("valid_points")
            if n is not None and int(n) > 0 and "z_um" in f and f["z_um"].ndim == 2 and min(
                    f["z_um"].shape) >= 2:
                return None
    except (OSError, KeyError, ValueError, TypeError):
        pass  # the full read below names the problem
    try:
        read_areal(path)
    except RawDataError as exc:
        return str(exc)
    return None
