"""Load and validate ``config.yaml``, in the workflow and outside it (notebooks, tests,
benchmarks).

The Snakefile validates with :func:`validate_config` too: the same JSON schema
(``src/robomill/data/schemas/config.schema.yaml`` and its per-section files) with the same default
filling, so library users get exactly the configuration the pipeline sees. The schemas are read
with libyaml's C loader (``snakemake.utils.validate`` read them through yte, ~0.4 s of every
workflow start) and a bad key is one line naming it.
"""

from __future__ import annotations

import copy
import math
import os
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import yaml

from robomill.errors import ConfigError
from robomill.settings import SECTIONS


def _load_yaml(path: Path) -> Any:
    """``yaml.safe_load`` with libyaml's C loader where PyYAML has it (the same YAML 1.1
    resolution, several times faster: the schemas are read at every workflow start)."""
    with open(path) as fh:
        return yaml.load(fh, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))




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


# ---- values as users write them ----------------------------------------------------------------
_BOOLEANS = {"true": True, "yes": True, "on": True, "false": False, "no": False, "off": False}


def _key_path(prefix: tuple[str, ...], path) -> str:
    key = ".".join(prefix)
    for part in path:
        key += f"[{part}]" if isinstance(part, int) else (f".{part}" if key else str(part))
    return key or "<root>"


def _types(schema_type: Any) -> list[str]:
    return [schema_type] if isinstance(schema_type, str) else list(schema_type or [])


def coerce_value(text: str, wanted: list[str]) -> tuple[bool, Any]:
    """``text`` as the first JSON-schema type of ``wanted`` it spells, as YAML 1.2 would
    read it: ``(True, value)``, or ``(False, None)`` when it spells none of them.

    ``integer``: ``10``, ``1e3``, ``10.0`` (integral values only); ``number``: any float
    Python reads (``6.0e8``, ``6e8``, ``1.5``, ``inf`` excluded); ``boolean``: true/false,
    yes/no, on/off; ``null``: ``null``, ``~`` or empty. PyYAML implements YAML 1.1, whose
    floats need a dot and a signed exponent: ``6.0e+8`` is a number there but ``6.0e8`` and
    ``6e8`` are text (YAML 1.2 reads all three as numbers); Snakemake's ``--config`` parser
    reads nested values as text.
    """
    t = text.strip()
    for typ in wanted:
        if typ in ("integer", "number"):
            try:
                value = float(t)
            except ValueError:
                continue
            if not math.isfinite(value):
                continue
            if typ == "integer" or (value.is_integer() and "." not in t and "e" not in t.lower()):
                if not value.is_integer():
                    continue
                return True, int(value)
            return True, value
        if typ == "boolean" and t.lower() in _BOOLEANS:
            return True, _BOOLEANS[t.lower()]
        if typ == "null" and t.lower() in ("null", "~", ""):
            return True, None
    return False, None


_NAMES = {"integer": "an integer", "number": "a number", "boolean": "true or false",
          "null": "null"}
_EXAMPLES = {"integer": "10", "number": "2.5e+2", "boolean": "true", "null": "null"}


def _fix_hint(key: str, text: str, wanted: list[str]) -> str:
    """The message for a text value that spells none of the ``wanted`` types, with the fix."""
    leaf = key.rsplit(".", 1)[-1].split("[")[0]
    typ = next((w for w in wanted if w in _EXAMPLES), "null")
    example = _EXAMPLES[typ]
    section = key.split(".")[0].split("[")[0]
    inline = f"{{{leaf}: {example}}}" if "." in key else example
    what = " or ".join(_NAMES.get(w, w) for w in wanted)
    return (f"config key '{key}': {text!r} is not {what} (expected {what}: write e.g. "
            f"{leaf}: {example} in the config file, or --config {section}='{inline}' on the "
            "command line)")


def coerce_numbers(node: Any, schema_path: str | Path, prefix: tuple[str, ...] = ()) -> list[str]:
    """Convert, in place, text values of ``node`` where its schema wants a number, an integer,
    a boolean or null and the text spells one (:func:`coerce_value`); return one line per
    conversion (``forces.decimation: '10' -> 10``).

    Config values as users write them: ``Kt_N_m2: 6.0e8`` in a YAML file and
    ``--config forces='{decimation: 10}'`` both reach the configuration as text.

    Raises
    ------
    ConfigError
        A text value where the schema wants a number that does not spell one; the message
        gives the exact fix.
    """
    import jsonschema

    validator = jsonschema.Draft202012Validator(_load_yaml(Path(schema_path)))
    done: list[str] = []
    for _ in range(10_000):  # each pass fixes every reachable error; nested ones need more
        changed = False
        for err in validator.iter_errors(node):
            if err.validator != "type" or not isinstance(err.instance, str):
                continue
            wanted = _types(err.validator_value)
            if not set(wanted) & {"integer", "number", "boolean", "null"}:
                continue
            key = _key_path(prefix, err.absolute_path)
            ok, value = coerce_value(err.instance, wanted)
            if not ok:
                raise ConfigError(_fix_hint(key, err.instance, wanted))
            parent = node
            *head, last = list(err.absolute_path) or [None]
            if last is None:
                continue
            for part in head:
                parent = parent[part]
            parent[last] = value
            done.append(f"{key}: {err.instance!r} -> {value!r}")
            changed = True
        if not changed:
            return done
    return done


def normalize_data(config: dict[str, Any]) -> None:
    """``data: <folder>`` (``--config data=FOLDER``) means raw data from that folder:
    ``{source: raw, raw_dir: FOLDER}``; ``data: synthetic`` means ``{source: synthetic}``.
    A mapping is left as it is."""
    data = config.get("data")
    if isinstance(data, str):
        config["data"] = ({"source": "synthetic"} if data.strip() == "synthetic"
                          else {"source": "raw", "raw_dir": data})


MOVED_KEYS: dict[tuple[str, ...], str] = {
    ("calibration", "mass_model"):
        "the link and tool masses are facts of the cell (written into cell.yaml): move the "
        "mapping {links, tool} from calibration: to cell: as cell.mass_model",
    ("synth", "ctrack", "mass_model"):
        "the documented masses are cell.mass_model (a fact of the cell); the virtual robot's "
        "true masses equal them unless synth.ctrack.true_mass_model plants a deviation: move "
        "the mapping to cell.mass_model (or to synth.ctrack.true_mass_model if it differs on "
        "purpose)",
}
"""Keys that older configurations set and that moved, with the exact fix
(:func:`refuse_moved_keys`)."""


def refuse_moved_keys(config: Mapping[str, Any]) -> None:
    """Refuse a configuration that sets a key listed in :data:`MOVED_KEYS`.

    Raises
    ------
    ConfigError
        ``config key 'calibration.mass_model' was moved: …`` with the fix.
    """
    for keys, fix in MOVED_KEYS.items():
        node: Any = config
        for k in keys:
            node = node.get(k) if isinstance(node, Mapping) else None
        if node is not None:
            raise ConfigError(f"config key '{'.'.join(keys)}' was moved: {fix}")


def prepare_config(config: dict[str, Any], schema_path: str | Path) -> list[str]:
    """Before validation, in place: a key that moved is refused with its fix
    (:func:`refuse_moved_keys`), the ``data`` shorthand (:func:`normalize_data`), then
    text values converted where the schema wants numbers (:func:`coerce_numbers`) at the top
    level and in every present section. The Snakefile calls this on Snakemake's ``config``
    before ``validate``; :func:`validate_config` calls it on its copy."""
    schema_path = Path(schema_path)
    refuse_moved_keys(config)
    normalize_data(config)
    done = coerce_numbers(config, schema_path)
    for keys, name in SECTIONS:
        node: Any = config
        for k in keys:
            node = node.get(k) if isinstance(node, dict) else None
        if isinstance(node, dict):
            done += coerce_numbers(node, schema_path.parent / "config" / f"{name}.schema.yaml",
                                   keys)
    return done


def validate_config(config: Mapping[str, Any], schema_path: str | Path) -> dict[str, Any]:
    """Validate ``config`` against the top-level schema and every section's schema, filling
    defaults; return the filled copy. Text spelling a number where the schema wants one is
    converted first (:func:`prepare_config`).

    Raises
    ------
    ConfigError
        Naming the offending key path (e.g. ``experiment.sets[0].depth_mm``) and the reason.
    """
    cfg = copy.deepcopy(dict(config))
    schema_path = Path(schema_path)
    prepare_config(cfg, schema_path)
    _check(cfg, schema_path, ())
    for keys, name in SECTIONS:
        node = cfg
        for k in keys:
            node = node[k]
        _check(node, schema_path.parent / "config" / f"{name}.schema.yaml", keys)
    return cfg


#: validated configurations kept by :func:`validate_config_cached`, newest first
CONFIG_CACHE_ENTRIES = 16


def _validation_key(config: Mapping[str, Any], schema_path: Path) -> str | None:
    """A digest of everything :func:`validate_config`'s answer depends on: the configuration
    as given, and the name, size and modification time of every schema file and of this
    module (the validator). None when the configuration cannot be pickled."""
    import hashlib
    import pickle

    try:
        blob = pickle.dumps(dict(config), protocol=5)
    except Exception:  # noqa: BLE001 (no cache for an unusual configuration, still validated)
        return None
    digest = hashlib.sha256(blob)
    files = [schema_path, *(schema_path.parent / "config" / f"{name}.schema.yaml"
                            for _, name in SECTIONS), Path(__file__)]
    for f in files:
        try:
            st = f.stat()
        except OSError:
            return None
        digest.update(f"{f.resolve()}|{st.st_size}|{st.st_mtime_ns}\n".encode())
    return digest.hexdigest()


def validate_config_cached(config: Mapping[str, Any], schema_path: str | Path,
                           cache_dir: str | Path) -> dict[str, Any]:
    """:func:`validate_config`, its answer kept in ``cache_dir`` for the next run with the
    same configuration and schemas (:func:`_validation_key`): the workflow validates at
    every start, ~0.15 s of a no-op rerun here, and a configuration is mostly rerun as it
    was. A refused configuration is never kept (it is refused again, with the same line); an
    unreadable cache entry is validated afresh."""
    import pickle

    schema_path = Path(schema_path)
    key = _validation_key(config, schema_path)
    entry = Path(cache_dir) / f"{key}.pickle" if key else None
    if entry is not None and entry.is_file():
        try:
            with open(entry, "rb") as fh:
                return pickle.load(fh)
        except Exception:  # noqa: BLE001,S110 (a torn or stale entry: validate again)
            pass
    checked = validate_config(config, schema_path)
    if entry is not None:
        try:
            entry.parent.mkdir(parents=True, exist_ok=True)
            partial = entry.with_suffix(f".{os.getpid()}.partial")
            with open(partial, "wb") as fh:
                pickle.dump(checked, fh, protocol=5)
            partial.replace(entry)
            kept = sorted(entry.parent.glob("*.pickle"), key=lambda p: p.stat().st_mtime,
                          reverse=True)
            for old in kept[CONFIG_CACHE_ENTRIES:]:
                old.unlink(missing_ok=True)
        except OSError:
            pass  # a read-only folder: no cache, the answer stands
    return checked


def load_config(path: str | Path = "config.yaml",
                schema_path: str | Path | None = None) -> dict[str, Any]:
    """Read ``config.yaml`` (safe loader) and validate it; ``schema_path`` defaults to the
    repository's ``src/robomill/data/schemas/config.schema.yaml`` beside the config file."""
    path = Path(path)
    if schema_path is None:
        from robomill.settings import SCHEMAS

        schema_path = SCHEMAS / "config.schema.yaml"
    return validate_config(_load_yaml(path) or {}, schema_path)


def repo_root(start: str | Path | None = None) -> Path:
    """The repository root (the folder holding ``Snakefile``), searched upwards."""
    here = Path(start or Path.cwd()).resolve()
    for p in [here, *here.parents]:
        if (p / "Snakefile").exists() and (p / "workflow").is_dir():
            return p
    src_root = Path(__file__).resolve().parents[3]
    if (src_root / "Snakefile").exists():
        return src_root
    raise FileNotFoundError(f"no robomill checkout (Snakefile + workflow/) above {here}")



def run_folder(config: dict[str, Any]) -> str | None:
    """The run's folder the configuration names (top-level ``workdir``), or None: run here.

    ``results/``, the virtual cell's raw folder and the logs are written there (the Snakefile
    enters it by Snakemake's ``workdir`` directive; :func:`check_run_folder`), so that a run of
    other cuts leaves this study's results as they are: the next experiment's configuration
    (``results/plan/next/config.yaml``) names ``results/plan/next/run``
    (:data:`robomill.plan.NEXT_RUN_DIR`). A relative ``data.raw_dir`` (each of
    ``data.raw_dirs``) keeps meaning a folder relative to where the run started: it is made
    absolute here, in place, before the working directory changes.
    """
    folder = config.get("workdir")
    if not folder:
        return None
    data = config.get("data")
    if isinstance(data, dict) and data.get("raw_dir"):
        data["raw_dir"] = str(Path(data["raw_dir"]).resolve())
    if isinstance(data, dict) and data.get("raw_dirs"):
        data["raw_dirs"] = [str(Path(d).resolve()) for d in data["raw_dirs"]]
    return str(folder)


def check_run_folder(folder: str, started_in: str | Path, now: str | Path) -> None:
    """Stop unless the run is in its folder ``folder`` (config ``workdir``, relative to
    ``started_in``, where the run started) now that the Snakefile's ``workdir`` directive ran.

    Snakemake enters the directive's folder, except under ``snakemake --directory D``, where
    it stays in D: then D must be the run's folder itself (its path ends with ``folder``,
    e.g. ``--directory STUDY/results/plan/next/run``), or the run would write the planned
    cuts' ``results/`` over the study's in D.

    Raises
    ------
    ConfigError
        One line naming the folder, where the run would write, and the two commands that
        run it in its own folder.
    """
    started, here = Path(started_in).resolve(), Path(now).resolve()
    wanted = Path(folder)
    if here == (started / wanted).resolve():
        return
    if not wanted.is_absolute() and here.parts[-len(wanted.parts):] == wanted.parts:
        return
    if wanted.is_absolute() and here == wanted.resolve():
        return
    raise ConfigError(
        f"config key 'workdir': the run's folder is {folder!r}, but snakemake --directory "
        f"keeps the run in {here} (it overrides the workdir directive), where it would "
        f"write over that folder's results/; run without --directory from {here}, or give "
        f"--directory {(here / wanted).resolve()}")
