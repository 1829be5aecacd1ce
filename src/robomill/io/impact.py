"""Impact-test files read: hammer + accelerometer hits (CSV or UFF 58 time histories), FRFs
(UFF 58), and the FRF artefact. (The UFF writers of the modal results live in
:mod:`robomill.modal.uff`; ``write_frf_uff`` and ``write_modes_uff`` stay importable here.)

``impact/<name>.csv`` (``docs/data-contract.md``): columns ``t_s, force_N`` and any non-empty
subset of ``ax_ms2, ay_ms2, az_ms2``; uniform, strictly increasing time; at least 64 rows.
Manifest keys of an impact entry (:func:`entry_metadata`): ``direction`` (the hammer's,
``X``/``+X``/``-X``…; CSV only), ``hit``, ``node`` (the node hit, default 1),
``response_node`` (where the accelerometer sits, default ``node``: a driving point),
``range_N`` and ``range_ms2`` (sensor ranges, optional: without them an overload is found by
flat-topping alone), ``tcp_mm`` (optional: the robot's TCP point [mm, base frame] where the
test was made, the pose at which its modes hold; every entry stating it states the same,
:func:`stated_tcp_mm`).

UFF 58 ("function at nodal DOF", what modal test software exports), read with ``pyuff``:

* function type 1 (time response): a hammer-force set (ordinate code 13) followed by the
  acceleration sets of the same hit (code 12); every force set starts a new hit. The hit's
  reference point is the force set's node and direction, the response points those of the
  acceleration sets (:func:`read_hits_uff`).
* function type 4 (frequency response) and 6 (coherence): :func:`read_frf_uff`. The FRF form
  follows from the ordinate/denominator codes: 8/13 receptance, 11/13 mobility, 12/13
  accelerance (:data:`FRF_FORMS`); each is turned into receptance (m/N). Any other code is
  refused, naming it.

Directions are UFF codes: X=1, Y=2, Z=3, negative for the negative axis.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr

from robomill.errors import RawDataError
from robomill.io.tables import check_uniform, read_numeric_csv

ACCEL_COLUMNS = ("ax_ms2", "ay_ms2", "az_ms2")
"""Response columns of a hit CSV (any non-empty subset), along +X, +Y, +Z."""
COLUMNS = ("t_s", "force_N", *ACCEL_COLUMNS)
DOF_CODE = {"X": 1, "Y": 2, "Z": 3}
"""UFF direction codes of the base axes."""
MIN_ROWS = 64
FRF_FORMS = {(8, 13): "receptance", (11, 13): "mobility", (12, 13): "accelerance"}
"""UFF 58 ordinate/denominator specific-data-type codes of an FRF → its form."""
FORCE_CODE, ACCEL_CODE = 13, 12
"""UFF 58 ordinate codes of a hammer force and an acceleration time history."""
G_MS2 = 9.80665
"""Standard gravity, for accelerations exported in g."""


@dataclass
class HitRecord:
    """One hit: force, responses and where they were measured.

    ``accel_ms2`` is ``(n, k)``, one column per ``responses`` point ``(node, direction
    code)``; ``reference`` is the hammer's point; ``source`` the file (and data set).
    """

    fs_hz: float
    force_N: np.ndarray
    accel_ms2: np.ndarray
    reference: tuple[int, int]
    responses: tuple[tuple[int, int], ...]
    source: str
    columns: tuple[str, ...] = ()


def entry_metadata(manifest_path: str | Path, entry: Mapping[str, Any],
                   index: int | None = None) -> dict[str, Any]:
    """Validated impact metadata of one manifest entry, with defaults filled.

    Returns ``{direction (int code or None for UFF), hit, node, response_node, range_N,
    range_ms2, tcp_mm (a tuple of 3 floats or None)}``.

    Raises
    ------
    RawDataError
        Naming the manifest and the key: a CSV entry without ``direction``, a direction that
        is not ±X/±Y/±Z, a hit that is not an integer, a node that is not a positive
        integer, a range that is not a positive number, a ``tcp_mm`` that is not three
        finite numbers.
    """
    from robomill.modal.layout import parse_direction

    where = f"files[{index}]" if index is not None else f"file {entry.get('path')}"
    path = str(entry.get("path", ""))
    is_uff = path.lower().endswith((".uff", ".unv"))
    hit = entry.get("hit", 1)
    if isinstance(hit, bool) or not isinstance(hit, (int, np.integer)):
        raise RawDataError(manifest_path, f"hit {hit!r} is not a hit number",
                           where=f"{where}.hit", expected="an integer (1, 2, …)")
    out: dict[str, Any] = {"direction": None, "hit": int(hit)}
    if "direction" in entry or not is_uff:
        if "direction" not in entry:
            raise RawDataError(manifest_path, "impact CSV entry without 'direction'",
                               where=f"{where}.direction",
                               expected="the hammer direction X, Y, Z (or +X, -X, …)")
        try:
            out["direction"] = parse_direction(entry["direction"])
        except ValueError as exc:
            raise RawDataError(manifest_path, str(exc), where=f"{where}.direction",
                               expected="X, Y, Z, +X, -X, +Y, -Y, +Z or -Z") from None
    for key, default in (("node", 1), ("response_node", None)):
        v = entry.get(key, default if default is not None else out.get("node"))
        if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or v < 1:
            raise RawDataError(manifest_path, f"{key} {v!r} is not a node number",
                               where=f"{where}.{key}", expected="a positive integer")
        out[key] = int(v)
    for key in ("range_N", "range_ms2"):
        v = entry.get(key)
        if v is not None and (isinstance(v, bool) or not isinstance(v, (int, float))
                              or not v > 0):
            raise RawDataError(manifest_path, f"{key} {v!r} is not a sensor range",
                               where=f"{where}.{key}", expected="a positive number")
        out[key] = None if v is None else float(v)
    v = entry.get("tcp_mm")
    if v is not None and not (isinstance(v, list | tuple) and len(v) == 3 and all(
            isinstance(x, int | float) and not isinstance(x, bool) and np.isfinite(x)
            for x in v)):
        raise RawDataError(manifest_path, f"tcp_mm {v!r} is not a point",
                           where=f"{where}.tcp_mm",
                           expected="[x, y, z] in mm, the TCP in the robot's base frame")
    out["tcp_mm"] = None if v is None else tuple(float(x) for x in v)
    return out


def stated_tcp_mm(manifest_path: str | Path, entries: Sequence[Mapping[str, Any]]
                ) -> tuple[float, float, float] | None:
    """The TCP point [mm] the impact entries state (``tcp_mm``), None where none states it.

    Raises
    ------
    RawDataError
        Two entries that state different points (one test, one pose: within 1e-6 mm).
    """
    stated = [(k, entry_metadata(manifest_path, f, k)["tcp_mm"]) for k, f in enumerate(entries)]
    stated = [(k, p) for k, p in stated if p is not None]
    if not stated:
        return None
    k0, p0 = stated[0]
    for k, p in stated[1:]:
        if np.max(np.abs(np.subtract(p, p0))) > 1e-6:
            raise RawDataError(manifest_path, f"tcp_mm {list(p)} differs from files[{k0}]'s "
                               f"{list(p0)}", where=f"files[{k}].tcp_mm",
                               expected="one TCP point for the whole impact test")
    return p0


def read_hit_record(path: str | Path, *, fs_hz: float | None = None,
                    reference: tuple[int, int] = (1, 1),
                    response_node: int = 1) -> HitRecord:
    """Read one hit CSV: ``t_s, force_N`` and the response columns present.

    Raises
    ------
    RawDataError
        Missing ``t_s``/``force_N``, no response column, text or NaN in a field, a truncated
        row, fewer than 64 rows, or a time column that is not uniform and strictly increasing
        (or whose spacing disagrees with ``fs_hz`` when given).
    """
    import csv

    path = Path(path)
    header: list[str] = []
    if path.exists():
        with path.open(newline="", encoding="utf-8-sig", errors="replace") as fh:
            header = [h.strip() for h in next(csv.reader(fh), [])]
    present = [c for c in ACCEL_COLUMNS if c in header]
    # a response column in another unit or misspelt (az_ms, ax_g) is not silently dropped:
    # asking for the contract's name gives the reader's unit/spelling hint
    for h in header:
        if h[:3] in ("ax_", "ay_", "az_") and h not in ACCEL_COLUMNS:
            present.append(f"{h[:2]}_ms2")
    present = [c for c in ACCEL_COLUMNS if c in present]
    if path.exists() and header and not present and "t_s" in header and "force_N" in header:
        raise RawDataError(path, "no response column", where="header (row 1)",
                           expected="at least one of " + ", ".join(ACCEL_COLUMNS))
    df = read_numeric_csv(path, ("t_s", "force_N", *(present or ACCEL_COLUMNS)),
                          min_rows=MIN_ROWS)
    dt = check_uniform(path, df["t_s"].to_numpy(), "t_s",
                       step=None if fs_hz is None else 1.0 / fs_hz)
    responses = tuple((int(response_node), ACCEL_COLUMNS.index(c) + 1) for c in present)
    return HitRecord(1.0 / dt, df["force_N"].to_numpy(), df[present].to_numpy(),
                     tuple(reference), responses, str(path), tuple(present))


def read_hit(path: str | Path, *, fs_hz: float | None = None) -> tuple[float, np.ndarray,
                                                                        np.ndarray]:
    """Read one hit: ``(fs_hz, force_N (n,), accel_ms2 (n, k))``, k the response columns
    present (see :func:`read_hit_record`)."""
    rec = read_hit_record(path, fs_hz=fs_hz)
    return rec.fs_hz, rec.force_N, rec.accel_ms2


# ---- UFF 58 in ------------------------------------------------------------------------------
def read_uff58(path: str | Path) -> list[dict]:
    """All type-58 data sets of a universal file (``pyuff``), in file order.

    Raises
    ------
    RawDataError
        A missing file, one pyuff cannot read, or one without any UFF 58 data set.
    """
    import pyuff

    path = Path(path)
    if not path.exists():
        raise RawDataError(path, "file does not exist")
    try:
        sets = pyuff.UFF(str(path)).read_sets()
    except Exception as exc:  # pyuff raises bare Exception on malformed files
        raise RawDataError(path, f"not a readable universal file ({exc})",
                           expected="UFF data sets of type 58 (ASCII or binary)") from None
    if isinstance(sets, dict):
        sets = [sets]
    sets = [s for s in sets if isinstance(s, dict) and s.get("type") in (58, "58")]
    with path.open("rb") as fh:  # every universal data set ends with a line "    -1"
        fh.seek(max(0, path.stat().st_size - 4096))
        tail = fh.read().rstrip()
    if sets and not tail.endswith(b"-1"):
        raise RawDataError(path, "the last data set does not end with its '-1' line "
                           "(truncated file?)", where=f"after data set {len(sets)}",
                           expected="every data set closed by a line '    -1'")
    if not sets:
        raise RawDataError(path, "no UFF 58 data set",
                           expected="UFF 58 time histories (function type 1) or FRFs (4)")
    return sets


def uff_function_types(path: str | Path) -> set[int]:
    """Function types of the UFF 58 sets in a file (1 time response, 4 FRF, 6 coherence…)."""
    return {int(s.get("func_type", 0)) for s in read_uff58(path)}


def _where(n: int, s: Mapping) -> str:
    return f"data set {n + 1} ({str(s.get('id1', '')).strip()})"


def _signed_dir(path, n, s, key) -> int:
    try:
        d = int(s[key])
    except (KeyError, ValueError, TypeError):
        d = 0
    if abs(d) not in (1, 2, 3):
        raise RawDataError(path, f"direction code {s.get(key)!r} in {key}", where=_where(n, s),
                           expected="1, 2, 3 (X, Y, Z; negative for the negative axis)")
    return d


def _check_points(path, n, s) -> np.ndarray:
    """The set's ordinate values, checked against its declared length."""
    data = np.asarray(s.get("data", []))
    num = int(s.get("num_pts", data.size) or data.size)
    if data.size != num or data.size < 2:
        raise RawDataError(path, f"{data.size} values where the header declares {num} "
                           "(truncated file?)", where=_where(n, s),
                           expected=f"{num} ordinate values")
    return data


def _unit_scale(path, n, s, kind: str) -> float:
    """Scale of an ordinate to SI from its axis-units label (g → m/s², kN → N)."""
    label = str(s.get("ordinate_axis_units_lab", "")).strip().lower().replace(" ", "")
    if kind == "accel":
        table = {"g": G_MS2, "m/s^2": 1.0, "m/s2": 1.0, "m/s²": 1.0, "m/s**2": 1.0,
                 "mm/s^2": 1e-3, "mm/s2": 1e-3, "none": 1.0, "": 1.0}
    else:
        table = {"n": 1.0, "kn": 1e3, "lbf": 4.4482216152605, "none": 1.0, "": 1.0}
    if label not in table:
        raise RawDataError(path, f"ordinate units {label!r}", where=_where(n, s),
                           expected=("m/s^2 or g" if kind == "accel" else "N or kN")
                           + " (or NONE: SI)")
    return table[label]


def read_hits_uff(path: str | Path) -> list[HitRecord]:
    """Impact hits from UFF 58 time histories (function type 1).

    Every hammer-force set (ordinate code 13) starts a hit; the acceleration sets (code 12)
    that follow it, up to the next force set, are its responses. All sets of a hit share the
    sampling step and length.

    Raises
    ------
    RawDataError
        Naming the file and data set: no time history, a response before any force set, a
        hit without responses, an ordinate code other than 13 or 12, a direction code not
        ±1…3, unequal steps or lengths, truncated data, unknown units.
    """
    from robomill.modal.layout import point_label

    path = Path(path)
    sets = [(n, s) for n, s in enumerate(read_uff58(path)) if int(s.get("func_type", 0)) == 1]
    if not sets:
        raise RawDataError(path, "no time history (UFF 58 with function type 1)",
                           expected="a hammer force set (ordinate code 13) and acceleration "
                                    "sets (code 12) per hit")
    hits: list[dict] = []
    for n, s in sets:
        code = int(s.get("ordinate_spec_data_type", 0))
        data = _check_points(path, n, s).real.astype(float)
        step = float(s.get("abscissa_inc", 0) or 0)
        if int(s.get("abscissa_spacing", 1)) != 1 or not step > 0:
            raise RawDataError(path, f"abscissa spacing {s.get('abscissa_spacing')!r}, "
                               f"step {step!r}", where=_where(n, s),
                               expected="evenly spaced time (abscissa spacing 1, step > 0)")
        point = (int(s.get("rsp_node", 1)), _signed_dir(path, n, s, "rsp_dir"))
        if code == FORCE_CODE:
            hits.append({"force": data * _unit_scale(path, n, s, "force"), "step": step,
                         "ref": point, "resp": [], "acc": [], "first": n})
        elif code == ACCEL_CODE:
            if not hits:
                raise RawDataError(path, "acceleration before any hammer force set",
                                   where=_where(n, s),
                                   expected="each hit's force set (code 13) first")
            h = hits[-1]
            if abs(step - h["step"]) > 1e-9 * step or data.size != h["force"].size:
                raise RawDataError(path, f"{data.size} samples every {step:g} s",
                                   where=_where(n, s),
                                   expected=f"{h['force'].size} samples every {h['step']:g} s "
                                            "as the hit's force")
            h["resp"].append(point)
            h["acc"].append(data * _unit_scale(path, n, s, "accel"))
        else:
            raise RawDataError(path, f"ordinate code {code} in a time history",
                               where=_where(n, s),
                               expected=f"{FORCE_CODE} (force) or {ACCEL_CODE} (acceleration)")
    out = []
    for h in hits:
        if not h["resp"]:
            raise RawDataError(path, "hammer force without any acceleration set",
                               where=f"data set {h['first'] + 1}",
                               expected="acceleration sets (code 12) after the force")
        out.append(HitRecord(1.0 / h["step"], h["force"], np.column_stack(h["acc"]), h["ref"],
                             tuple(h["resp"]), f"{path} (data set {h['first'] + 1})",
                             tuple(point_label(*p) for p in h["resp"])))
    return out


def read_frf_uff(path: str | Path) -> xr.Dataset:
    """Read UFF 58 FRFs (type 4, any of :data:`FRF_FORMS`, turned into receptance) and
    coherences (type 6) into ``H`` and ``coherence`` over ``output, input, frequency`` with
    the node numbers and directions of each point (:func:`robomill.modal.frf_coords`).

    Raises
    ------
    RawDataError
        If the file is missing or not valid UFF, holds no type-58 FRF, the FRFs disagree in
        frequency axis, a direction code is not ±1…3, a set is shorter than its header
        says, an FRF's unit codes are not those of :data:`FRF_FORMS` (the codes are named),
        an FRF pair appears twice, or a coherence has no FRF.
    """
    from robomill.modal.frf import to_receptance
    from robomill.modal.layout import _point_key, frf_coords, point_label

    path = Path(path)
    sets = read_uff58(path)
    frfs = [(n, s) for n, s in enumerate(sets) if int(s.get("func_type", 0)) == 4]
    if not frfs:
        raise RawDataError(path, "no FRF data set (UFF 58 with function type 4)",
                           expected="FRFs H(response point, reference point)")
    f = np.asarray(frfs[0][1]["x"], float)
    by_pair: dict[tuple, np.ndarray] = {}
    coh_pair: dict[tuple, np.ndarray] = {}
    for n, s in enumerate(sets):
        ft = int(s.get("func_type", 0))
        if ft not in (4, 6):
            continue
        where = _where(n, s)
        pair = ((int(s.get("rsp_node", 1)), _signed_dir(path, n, s, "rsp_dir")),
                (int(s.get("ref_node", 1)), _signed_dir(path, n, s, "ref_dir")))
        data = _check_points(path, n, s)
        x = np.asarray(s.get("x", []), float)
        if x.shape != f.shape or not np.allclose(x, f):
            raise RawDataError(path, f"{data.size} points on a different frequency axis",
                               where=where, expected=f"{f.size} points from {f[0]:g} Hz "
                                                     f"every {f[1] - f[0]:g} Hz")
        if ft == 4:
            codes = (int(s.get("ordinate_spec_data_type", 0)),
                     int(s.get("orddenom_spec_data_type", 0)))
            if codes not in FRF_FORMS:
                raise RawDataError(path, f"FRF unit codes {codes[0]}/{codes[1]} "
                                   "(ordinate/denominator)", where=where,
                                   expected="8/13 receptance, 11/13 mobility or 12/13 "
                                            "accelerance")
            if pair in by_pair:
                raise RawDataError(path, f"FRF {point_label(*pair[0])}/"
                                   f"{point_label(*pair[1])} appears twice", where=where,
                                   expected="one FRF per response/reference pair")
            by_pair[pair] = to_receptance(np.asarray(data, complex), f, FRF_FORMS[codes])
        else:
            coh_pair[pair] = np.real(np.asarray(data))
    for pair in coh_pair:
        if pair not in by_pair:
            raise RawDataError(path, f"coherence {point_label(*pair[0])}/"
                               f"{point_label(*pair[1])} without its FRF",
                               expected="a type-4 FRF for every type-6 coherence")
    outs = sorted({p[0] for p in by_pair}, key=_point_key)
    ins = sorted({p[1] for p in by_pair}, key=_point_key)
    H = np.full((len(outs), len(ins), f.size), np.nan + 0j)
    coh = np.full(H.shape, np.nan)
    for (o, i), h in by_pair.items():
        H[outs.index(o), ins.index(i)] = h
        if (o, i) in coh_pair:
            coh[outs.index(o), ins.index(i)] = coh_pair[(o, i)]
    if f[0] == 0:
        H[..., 0] = np.nan
    ds = xr.Dataset(
        {"H": (("output", "input", "frequency"), H,
               {"units": "m/N", "long_name": "receptance FRF"}),
         "coherence": (("output", "input", "frequency"), coh,
                       {"units": "1", "long_name": "ordinary coherence"})},
        coords=frf_coords(f, outs, ins))
    if not coh_pair:
        ds = ds.drop_vars("coherence")
    return ds


def read_frf(path: str | Path) -> xr.Dataset:
    """Open ``results/modal/frf.nc`` with its complex variables (``H``, ``H2``) restored."""
    from robomill.io.artefacts import open_artefact
    from robomill.modal.ncio import join_complex

    return join_complex(open_artefact(path))


# ---- a whole impact test from the manifest ----------------------------------------------------
@dataclass
class ImpactTest:
    """The impact files of a study, read: hit records (with their manifest metadata) and
    FRF datasets (UFF 58 type 4)."""

    hits: list[tuple[HitRecord, dict[str, Any]]]
    frfs: list[xr.Dataset]
    paths: list[str]
    tcp_mm: tuple[float, float, float] | None = None
    """The TCP point [mm, base frame] where the test was made (:func:`stated_tcp_mm`)."""


def load_impact_test(manifest, entries: Sequence[Mapping[str, Any]]) -> ImpactTest:
    """Read every impact entry of a manifest (:class:`robomill.io.manifest.Manifest`).

    CSV entries are hits at ``(node, direction)`` with responses at ``response_node``
    (:func:`entry_metadata`, :func:`read_hit_record`; all at the first file's rate); ``.uff``
    entries hold time histories (:func:`read_hits_uff`), FRFs (:func:`read_frf_uff`) or both.
    Each hit's metadata carries ``path``, ``hit`` and the sensor ranges.

    Raises
    ------
    RawDataError
        A file that breaks the contract; a UFF file with neither time histories nor FRFs.
    """
    hits: list[tuple[HitRecord, dict[str, Any]]] = []
    frfs: list[xr.Dataset] = []
    paths: list[str] = []
    fs = None
    for k, f in enumerate(entries):
        meta = entry_metadata(manifest.path, f, k)
        path = manifest.verify_file(f["path"])
        paths.append(str(path))
        if str(f["path"]).lower().endswith((".uff", ".unv")):
            types = uff_function_types(path)
            if not types & {1, 4}:
                raise RawDataError(path, f"UFF 58 function types {sorted(types)}",
                                   expected="time histories (1) or FRFs (4)")
            if 4 in types:
                frfs.append(read_frf_uff(path))
            if 1 in types:
                for n, rec in enumerate(read_hits_uff(path), start=1):
                    hits.append((rec, {**meta, "path": f"{f['path']}#{n}", "hit": n}))
            continue
        rec = read_hit_record(path, fs_hz=fs, reference=(meta["node"], meta["direction"]),
                              response_node=meta["response_node"])
        fs = fs or rec.fs_hz
        hits.append((rec, {**meta, "path": f["path"], "hit": meta["hit"]}))
    return ImpactTest(hits, frfs, paths, stated_tcp_mm(manifest.path, entries))

