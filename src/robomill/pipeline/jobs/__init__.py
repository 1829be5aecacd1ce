"""Jobs of the workflow as one library call each: a rule's script unpacks its inputs, outputs
and parameters and calls one function here, which reads the files, calls the science and
writes the artefacts (the science itself reads and writes no artefact:
``tests/test_boundaries.py``).

Each script passes the rule's own objects — ``snakemake.input``, ``snakemake.output``,
``snakemake.params`` (Snakemake's named lists: read by attribute or by name) and its logger
(:func:`robomill.pipeline.runlog.setup`) — and nothing composed: ``tests/test_rule_scripts.py``.
A job module is named after its script, so that a rule's ``code`` inputs (the library files
its script imports, :mod:`robomill.pipeline.codedeps`) stay the modules that rule uses.
"""

from __future__ import annotations

from collections.abc import Iterable


def path_list(paths: str | Iterable[str]) -> list[str]:
    """A rule's input or output as a list of paths (one path, a string, is a list of one)."""
    return [paths] if isinstance(paths, str) else [str(p) for p in paths]
