"""List the artefacts of a run: what each holds, with units, and which rule made it."""

from __future__ import annotations

from pathlib import Path

import pandas as pd
import xarray as xr


def list_artefacts(results_dir: str | Path = "results") -> pd.DataFrame:
    """One row per netCDF artefact under ``results_dir``.

    Columns: ``name`` (path relative to ``results_dir`` without suffix), ``path``, ``dims``
    (``{dim: size}``), ``variables`` (``"name [units]"`` list), ``rule`` (producer).
    Files are opened lazily (metadata only), so listing a large run is quick.
    """
    root = Path(results_dir)
    rows = []
    for path in sorted(root.rglob("*.nc")):
        if any(part.startswith(".") for part in path.relative_to(root).parts):
            continue
        try:
            with xr.open_dataset(path, engine="h5netcdf") as ds:
                rows.append({
                    "name": path.relative_to(root).with_suffix("").as_posix(),
                    "path": str(path),
                    "dims": dict(ds.sizes),
                    "variables": [f"{v} [{ds[v].attrs.get('units', '?')}]"
                                  for v in ds.data_vars],
                    "rule": ds.attrs.get("rule", ""),
                })
        except (OSError, ValueError) as exc:  # a file being written, or not an artefact
            rows.append({"name": path.stem, "path": str(path), "dims": {},
                         "variables": [], "rule": f"unreadable: {exc}"})
    return pd.DataFrame(rows, columns=["name", "path", "dims", "variables", "rule"])
