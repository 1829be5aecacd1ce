"""Load and validate ``config.yaml`` outside Snakemake (notebooks, tests, benchmarks).

The Snakefile validates with ``snakemake.utils.validate``; this function applies the same
JSON schema (``workflow/schemas/config.schema.yaml`` and its per-section files) with the same
default filling, so library users get exactly the configuration the pipeline sees.
"""

from __future__ import annotations

import copy
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import yaml

from robomill.io.errors import ConfigError


def _load_yaml(path: Path) -> Any:
    with open(path) as fh:
        return yaml.safe_load(fh)


SECTIONS: tuple[tuple[tuple[str, ...], str], ...] = (
    (("data",), "data"),
    (("cell",), "cell"),
    (("experiment",), "experiment"),
    (("synth",), "synth"),
    (("synth", "profilometer"), "synth_profilometer"),
    (("synth", "dynamometer"), "synth_dynamometer"),
    (("synth", "tracker"), "synth_tracker"),
    (("synth", "impact"), "synth_impact"),
    (("synth", "ctrack"), "synth_ctrack"),
    (("synth", "loadtests"), "synth_loadtests"),
    (("chapters",), "chapters"),
    (("calibration",), "calibration"),
    (("surface",), "surface"),
    (("forces",), "forces"),
    (("straightness",), "straightness"),
    (("modal",), "modal"),
    (("chatter",), "chatter"),
    (("stiffness",), "stiffness"),
    (("hexapod",), "hexapod"),
)
"""Config sections and their schema files ``workflow/schemas/config/<name>.schema.yaml``,
validated in this order after the top-level ``config.schema.yaml`` (the Snakefile does the
same with ``snakemake.utils.validate``)."""


def _validator(schema_path: Path):
    import jsonschema

    schema = _load_yaml(schema_path)
    base_cls = jsonschema.Draft202012Validator

    def set_defaults(validator, properties, instance, schema):
        if isinstance(instance, dict):
            for prop, sub in properties.items():
                if "default" in sub and prop not in instance:
                    instance[prop] = copy.deepcopy(sub["default"])
        yield from base_cls.VALIDATORS["properties"](validator, properties, instance, schema)

    cls = jsonschema.validators.extend(base_cls, {"properties": set_defaults})
    return cls(schema)


def _check(instance: Any, schema_path: Path, prefix: tuple[str, ...]) -> None:
    validator = _validator(schema_path)
    errors = sorted(validator.iter_errors(instance),
                    key=lambda e: [str(p) for p in e.absolute_path])
    if errors:
        err = errors[0]
        key = ".".join(prefix)
        for part in err.absolute_path:
            key += f"[{part}]" if isinstance(part, int) else (f".{part}" if key else str(part))
        raise ConfigError(f"config key '{key or '<root>'}': {err.message} "
                          f"(schema {schema_path.name})")


def validate_config(config: Mapping[str, Any], schema_path: str | Path) -> dict[str, Any]:
    """Validate ``config`` against the top-level schema and every section's schema, filling
    defaults; return the filled copy.

    Raises
    ------
    ConfigError
        Naming the offending key path (e.g. ``experiment.sets[0].depth_mm``) and the reason.
    """
    cfg = copy.deepcopy(dict(config))
    schema_path = Path(schema_path)
    _check(cfg, schema_path, ())
    for keys, name in SECTIONS:
        node = cfg
        for k in keys:
            node = node[k]
        _check(node, schema_path.parent / "config" / f"{name}.schema.yaml", keys)
    return cfg


def load_config(path: str | Path = "config.yaml",
                schema_path: str | Path | None = None) -> dict[str, Any]:
    """Read ``config.yaml`` (safe loader) and validate it; ``schema_path`` defaults to the
    repository's ``workflow/schemas/config.schema.yaml`` beside the config file."""
    path = Path(path)
    if schema_path is None:
        schema_path = repo_root(path) / "workflow" / "schemas" / "config.schema.yaml"
    return validate_config(_load_yaml(path) or {}, schema_path)


def repo_root(start: str | Path | None = None) -> Path:
    """The repository root (the folder holding ``Snakefile``), searched upwards."""
    here = Path(start or Path.cwd()).resolve()
    for p in [here, *here.parents]:
        if (p / "Snakefile").exists() and (p / "workflow").is_dir():
            return p
    src_root = Path(__file__).resolve().parents[2]
    if (src_root / "Snakefile").exists():
        return src_root
    raise FileNotFoundError(f"no robomill checkout (Snakefile + workflow/) above {here}")
