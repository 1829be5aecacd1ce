"""Building blocks of self-describing datasets: every variable and coordinate with its units.

One subject: the ``(dims, data, attrs)`` tuples that :class:`xarray.Dataset` takes, so each
science module states a variable's units and long name in one call (DESIGN principle 3).
"""

from __future__ import annotations

import numpy as np


def attrs(units: str, long_name: str) -> dict[str, str]:
    """The two attributes every artefact variable carries."""
    return {"units": units, "long_name": long_name}


def var(dims, data, units: str, long_name: str) -> tuple:
    """A data variable ``(dims, array, attrs)`` for :class:`xarray.Dataset`."""
    return (dims, np.asarray(data), attrs(units, long_name))


def coord(name: str, values, units: str, long_name: str, dtype=float) -> tuple:
    """A one-dimensional coordinate ``(name, array, attrs)`` along its own dimension."""
    return (name, np.asarray(values, dtype), attrs(units, long_name))
