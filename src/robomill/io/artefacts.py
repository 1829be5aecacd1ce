"""Self-describing artefacts: xarray datasets in netCDF4/HDF5 (``h5netcdf``) and CSV tables.

Every artefact carries, as global attributes:

``rule``             the Snakemake rule (or function) that produced it
``robomill_version`` package version
``git_commit``       commit of the working tree that produced it (``unknown`` outside git)
``config_digest``    digest of the configuration section the producer used
``inputs_sha256``    JSON object ``{input path: sha256}`` of every input file

and every data variable and coordinate has ``units`` and ``long_name``
(``units = "1"`` for dimensionless quantities). :func:`write_artefact` refuses a dataset that
does not, so no unlabelled number leaves the pipeline.
"""

from __future__ import annotations

import functools
import json
import subprocess
from collections.abc import Iterable, Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd
import xarray as xr

from robomill.io.atomic import atomic_path
from robomill.io.hashing import config_digest, sha256_file

PROVENANCE_KEYS = ("rule", "robomill_version", "git_commit", "config_digest", "inputs_sha256")


@functools.cache
def git_commit(cwd: str | None = None) -> str:
    """The commit of the robomill checkout in use (``unknown`` outside a git checkout).

    By default git is asked in the package's own folder (an editable install lives in the
    repository), not in the working directory of the run.
    """
    if cwd is None:
        cwd = str(Path(__file__).resolve().parent)
    try:
        out = subprocess.run(
            ["git", "rev-parse", "HEAD"], cwd=cwd, capture_output=True, text=True, timeout=10
        )
    except (OSError, subprocess.SubprocessError):
        return "unknown"
    return out.stdout.strip() if out.returncode == 0 else "unknown"


def package_version() -> str:
    from robomill import __version__

    return __version__


def provenance(
    *, rule: str, inputs: Iterable[str | Path] = (), config_section: Any = None
) -> dict[str, str]:
    """The provenance attributes for an artefact produced by ``rule`` from ``inputs``."""
    shas = {str(p): sha256_file(p) for p in inputs}
    return {
        "rule": rule,
        "robomill_version": package_version(),
        "git_commit": git_commit(),
        "config_digest": config_digest(config_section) if config_section is not None else "",
        "inputs_sha256": json.dumps(shas, sort_keys=True),
    }


def _check_labelled(ds: xr.Dataset) -> None:
    missing = []
    for name, var in list(ds.data_vars.items()) + list(ds.coords.items()):
        for key in ("units", "long_name"):
            if key not in var.attrs:
                missing.append(f"{name}.{key}")
    if missing:
        raise ValueError(
            "artefact variables must carry 'units' and 'long_name' attrs; missing: "
            + ", ".join(missing)
        )


def _encodable(ds: xr.Dataset) -> xr.Dataset:
    """netCDF cannot hold bool or nested attrs; convert them losslessly."""
    ds = ds.copy()
    for name in list(ds.data_vars) + list(ds.coords):
        if ds[name].dtype == bool:
            attrs = dict(ds[name].attrs)
            attrs["dtype_bool"] = 1
            ds[name] = ds[name].astype("int8").assign_attrs(attrs)
    for obj in [ds] + [ds[v] for v in list(ds.data_vars) + list(ds.coords)]:
        for key, value in list(obj.attrs.items()):
            if isinstance(value, Mapping | list | tuple) and not isinstance(value, np.ndarray):
                if isinstance(value, list | tuple) and all(
                    isinstance(v, int | float | np.number) for v in value
                ):
                    continue
                obj.attrs[key] = json.dumps(value, default=str)
            elif isinstance(value, bool | np.bool_):
                obj.attrs[key] = int(value)
            elif value is None:
                obj.attrs[key] = ""
    return ds


def write_artefact(
    ds: xr.Dataset,
    path: str | Path,
    *,
    rule: str,
    inputs: Iterable[str | Path] = (),
    config_section: Any = None,
) -> Path:
    """Write ``ds`` to ``path`` (netCDF4 via h5netcdf) with provenance, atomically.

    Parameters
    ----------
    ds
        Dataset whose every variable and coordinate has ``units`` and ``long_name``.
    path
        Destination ``.nc`` file; parent folders are created.
    rule
        Name of the producing rule.
    inputs
        Input files; their sha256 go into ``inputs_sha256``.
    config_section
        The configuration the producer used (digest only is stored).

    Returns
    -------
    Path
        ``path``.

    Examples
    --------
    >>> import numpy as np, xarray as xr, tempfile, os
    >>> ds = xr.Dataset({"z": ("x", np.zeros(3), {"units": "um", "long_name": "height"})},
    ...                 coords={"x": ("x", np.arange(3.0), {"units": "mm", "long_name": "x"})})
    >>> p = write_artefact(ds, os.path.join(tempfile.mkdtemp(), "a.nc"), rule="doc")
    >>> open_artefact(p)["z"].attrs["units"]
    'um'
    """
    _check_labelled(ds)
    out = _encodable(ds)
    out.attrs.update(provenance(rule=rule, inputs=inputs, config_section=config_section))
    path = Path(path)
    with atomic_path(path) as tmp:
        out.to_netcdf(tmp, engine="h5netcdf", invalid_netcdf=False)
    return path


def open_artefact(path: str | Path, *, load: bool = True) -> xr.Dataset:
    """Open an artefact written by :func:`write_artefact` (bools restored).

    With ``load=True`` (default) the data are read into memory and the file is closed, so
    the file can be rewritten while the dataset is in use.
    """
    ds = xr.open_dataset(path, engine="h5netcdf")
    if load:
        ds = ds.load()
        ds.close()
    for name in list(ds.data_vars) + list(ds.coords):
        if ds[name].attrs.get("dtype_bool") == 1:
            restored = ds[name].astype(bool)
            restored.attrs = {k: v for k, v in ds[name].attrs.items() if k != "dtype_bool"}
            ds[name] = restored
    return ds


def write_table(df: pd.DataFrame, path: str | Path, *, index: bool = False,
                float_format: str | None = "%.6g") -> Path:
    """Write a CSV table atomically (tables are read by people: a fixed float format)."""
    path = Path(path)
    with atomic_path(path) as tmp:
        df.to_csv(tmp, index=index, float_format=float_format)
    return path
