"""Keep the start-up of every Snakemake run, Slurm job and chapter short.

jsonschema (Snakemake's config validation, nbformat in papermill) imports the optional
``rfc3987_syntax`` whenever it is installed (here it is, through jupyter-events'
``jsonschema[format-nongpl]``), and that module compiles 38 lark grammars at import: measured
on the 2-core development machine, ``import jsonschema`` takes 3.4 s with it and 0.35 s
without. It only adds the ``iri``/``iri-reference`` format checks, which no robomill schema
uses. :func:`skip_iri_format_checks` keeps it out of this process when jsonschema has not been
imported yet; the schemas are still validated by jsonschema in full.
"""

from __future__ import annotations

import sys


def skip_iri_format_checks() -> bool:
    """Block ``rfc3987_syntax`` for this process; True if it took effect."""
    if "jsonschema" in sys.modules or "rfc3987_syntax" in sys.modules:
        return False
    sys.modules["rfc3987_syntax"] = None  # makes `import rfc3987_syntax` raise ImportError
    return True
