"""The artefact catalogue: every artefact of the pipeline by name, and its path.

The catalogue is package data (``robomill/data/artefacts.yaml``): one entry per artefact,
grouped by stage (``forces: {mean_forces: results/forces/mean_forces.csv}``), its name the
stage and the key (``"forces.mean_forces"``). The workflow's rules, the findings and the plan's
check take an artefact's path from :func:`artefact`, so that a path is written once. A path
with ``{wildcards}`` is a Snakemake pattern (one file per cut, run, robot, ...): without
values it is returned as the pattern (a rule's output), with values filled
(``artefact("forces.cut", cut="A7")``).
"""

from __future__ import annotations

import difflib
import re
from functools import cache
from pathlib import Path

#: the package's artefact catalogue
CATALOGUE_FILE = Path(__file__).resolve().parent / "data" / "artefacts.yaml"

_WILDCARD = re.compile(r"\{(?P<name>[A-Za-z_][A-Za-z0-9_]*)\}")


class CatalogueError(KeyError):
    """A name the catalogue does not hold, or a wildcard its path does not have."""

    def __str__(self) -> str:
        return str(self.args[0])


@cache
def _load(path: str) -> dict[str, str]:
    import yaml

    data = yaml.safe_load(Path(path).read_text())
    flat: dict[str, str] = {}
    for stage, entries in data.items():
        for key, value in entries.items():
            flat[f"{stage}.{key}"] = str(value)
    paths: dict[str, str] = {}
    for name, value in flat.items():
        if value in paths:
            raise ValueError(f"{path}: {name} and {paths[value]} both name {value}")
        paths[value] = name
    return flat


def catalogue(path: str | Path | None = None) -> dict[str, str]:
    """Every artefact: name (``"forces.mean_forces"``) → path (below the run's folder), of the
    catalogue at ``path`` (default: the package's, :data:`CATALOGUE_FILE`)."""
    return dict(_load(str(path if path is not None else CATALOGUE_FILE)))


def wildcards(name: str) -> tuple[str, ...]:
    """The wildcards of artefact ``name``'s path, in order (``("cut",)``)."""
    return tuple(m["name"] for m in _WILDCARD.finditer(artefact(name)))


def artefact(name: str, **values: object) -> str:
    """The path of artefact ``name`` (``"forces.mean_forces"``), its ``{wildcards}`` filled
    from ``values`` where given (the others left as the pattern).

    Raises
    ------
    CatalogueError
        ``name`` is not in the catalogue (the message names the closest), or a value is
        given for a wildcard the path does not have.
    """
    table = _load(str(CATALOGUE_FILE))
    try:
        path = table[name]
    except KeyError:
        close = difflib.get_close_matches(name, table, n=1)
        raise CatalogueError(f"no artefact {name!r} in {CATALOGUE_FILE.name}"
                             + (f" (did you mean {close[0]!r}?)" if close else "")) from None
    have = {m["name"] for m in _WILDCARD.finditer(path)}
    unknown = sorted(set(values) - have)
    if unknown:
        raise CatalogueError(f"artefact {name!r} ({path}) has no wildcard {unknown[0]!r} "
                             f"(it has {sorted(have) or 'none'})")
    return _WILDCARD.sub(lambda m: str(values[m["name"]]) if m["name"] in values
                         else m.group(0), path)
