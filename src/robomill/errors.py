"""The error types of robomill: bad input data and a bad configuration.

They live at the package's top level so that the science modules, the readers, the importers
and the pipeline's tooling all raise the same types without importing one another
(:mod:`robomill.io` re-exports them). Every reader in
:mod:`robomill.io` raises :class:`RawDataError` when a file does not follow
``docs/data-contract.md``. The message always names the file, where in it the problem is
(row, column or key) and what was expected, so that a user can fix the file without reading
a traceback.
"""

from __future__ import annotations

from pathlib import Path


class RawDataError(ValueError):
    """A raw measurement file (or the manifest) does not follow the data contract.

    Parameters
    ----------
    path
        The offending file.
    problem
        What is wrong, e.g. ``"column 'z_um' is missing"``.
    where
        Row, column or key, e.g. ``"row 17, column x_mm"`` (optional).
    expected
        What the contract expects, e.g. ``"columns x_mm, z_um"`` (optional).
    """

    def __init__(self, path: str | Path, problem: str, *, where: str | None = None,
                 expected: str | None = None):
        self.path = str(path)
        self.problem = problem
        self.where = where
        self.expected = expected
        parts = [f"{self.path}"]
        if where:
            parts.append(f"{where}")
        msg = ": ".join(parts) + f": {problem}"
        if expected:
            msg += f" (expected {expected})"
        super().__init__(msg)


class ConfigError(ValueError):
    """The configuration does not follow ``src/robomill/data/schemas/config.schema.yaml``."""
