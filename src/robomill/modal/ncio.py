"""Complex FRF variables in netCDF: split into ``<name>_real``/``<name>_imag`` and joined
back (netCDF4 has no complex type)."""

from __future__ import annotations

import numpy as np
import xarray as xr

COMPLEX_VARS = ("H", "H2", "H_synth")
"""Complex FRF variables, stored in netCDF as ``<name>_real`` and ``<name>_imag``."""


def split_complex(ds: xr.Dataset) -> xr.Dataset:
    """Complex variables → ``<name>_real`` and ``<name>_imag`` (netCDF4 has no complex type)."""
    ds = ds.copy()
    for name in list(ds.data_vars):
        if np.iscomplexobj(ds[name].values):
            attrs = dict(ds[name].attrs)
            for part, fn in (("real", np.real), ("imag", np.imag)):
                ds[f"{name}_{part}"] = ds[name].copy(data=fn(ds[name].values)).assign_attrs(
                    {**attrs, "long_name": f"{part} part of {attrs.get('long_name', name)}"})
            ds = ds.drop_vars(name)
    return ds


def join_complex(ds: xr.Dataset) -> xr.Dataset:
    """Inverse of :func:`split_complex`: ``<name>_real`` + ``<name>_imag`` → complex ``name``."""
    ds = ds.copy()
    for name in [v[:-5] for v in ds.data_vars if str(v).endswith("_real")]:
        if f"{name}_imag" in ds:
            attrs = dict(ds[f"{name}_real"].attrs)
            attrs["long_name"] = attrs.get("long_name", name).removeprefix("real part of ")
            ds[name] = (ds[f"{name}_real"] + 1j * ds[f"{name}_imag"]).assign_attrs(attrs)
            ds = ds.drop_vars([f"{name}_real", f"{name}_imag"])
    return ds
