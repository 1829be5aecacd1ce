"""MATLAB ``.mat`` exports of an impact test → ``impact/<stem>_h<k>.csv`` (time records) or
``impact/<stem>.uff`` (an analyser's FRFs with their coherence).

Read with SciPy (:func:`scipy.io.loadmat`, MAT v4–v7) or h5py (MAT v7.3, an HDF5 file; its
arrays are stored transposed and complex numbers as ``real``/``imag`` pairs). Variables at
the top level and one level inside structs (``s.field``) are named as MATLAB names them.

* **Time records** (``--hammer``, ``--response``): a channel is a vector variable
  (``force``), a column of a matrix (``data[1]``: 1-based, the analyser's channel 1), or,
  where the file holds one matrix, just its column number (``1``). A three-dimensional
  matrix (samples × channels × records) is one record per page. The rate is ``--fs-hz``,
  else a scalar named ``fs``, ``Fs``, ``fsamp``, ``SampleRate``, ``sample_rate`` (Hz) or
  ``dt``, ``Ts`` (s), else a uniform time vector ``t``/``time``. A ``.mat`` file carries no
  units: they are stated on the command line (``--hammer force:N``, ``--response
  data[2]:X:g``). Hits are found and split as for every impact importer
  (:mod:`robomill.importers._impact`).
* **FRFs** (``--frf NAME``): the analyser's H1 (complex, frequencies × responses, or a
  vector), ``--freq`` its frequency vector [Hz], ``--coherence`` the coherence of the same
  shape (optional), ``--frf-unit`` what it is (``m/s^2/N``, ``g/N``, ``m/s/N``, ``m/N``,
  ``mm/N``, ``um/N``); each column's point is ``--response COL:DIR`` (1-based), the
  reference the hammer's ``--node`` and ``--direction``. They are turned into receptance
  and written as UFF 58 (function types 4 and 6, :func:`robomill.modal.uff.write_frf_uff`),
  the contract's FRF file, which the modal stage identifies as any measured FRF.
"""

from __future__ import annotations

import argparse
import re
from pathlib import Path

import numpy as np

from robomill.errors import RawDataError
from robomill.importers._common import nice_rate
from robomill.importers._impact import (
    ACCEL_UNITS,
    ChannelSpec,
    add_hit_arguments,
    append_hits,
    finish_hits,
    hammer_direction,
    parse_hammer,
    parse_response,
    safe_stem,
    scale_to_si,
    write_hits,
)

FORMAT = "mat"
KIND = "impact"
DESCRIPTION = ("MATLAB .mat (v5 or v7.3) impact test: hammer and accelerometer time records, "
               "or an analyser's H1 FRFs with coherence → impact/<stem>_h<k>.csv or "
               "impact/<stem>.uff")
WHAT = "a MATLAB .mat file (v4-v7 or v7.3)"
RATE_NAMES = ("fs", "Fs", "FS", "fsamp", "SampleRate", "sample_rate", "fs_hz", "Fs_Hz")
STEP_NAMES = ("dt", "Ts", "DT", "delta_t")
TIME_NAMES = ("t", "time", "Time", "t_s")
FRF_UNITS = {"m/s^2/n": ("accelerance", 1.0), "(m/s^2)/n": ("accelerance", 1.0),
             "m/s2/n": ("accelerance", 1.0), "g/n": ("accelerance", ACCEL_UNITS["g"]),
             "m/s/n": ("mobility", 1.0), "(m/s)/n": ("mobility", 1.0),
             "m/n": ("receptance", 1.0), "mm/n": ("receptance", 1e-3),
             "um/n": ("receptance", 1e-6), "µm/n": ("receptance", 1e-6)}
"""``--frf-unit`` → (FRF form, factor to SI)."""
_COLUMN = re.compile(r"^(.+?)\[(\d+)\]$")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """Impact options and the FRF ones."""
    add_hit_arguments(parser)
    parser.add_argument("--frf", default=None, metavar="NAME",
                        help="an analyser's FRF variable (complex; frequencies x responses)")
    parser.add_argument("--freq", default=None, metavar="NAME",
                        help="its frequency vector [Hz] (with --frf)")
    parser.add_argument("--coherence", default=None, metavar="NAME",
                        help="its coherence, same shape (with --frf; optional)")
    parser.add_argument("--frf-unit", default=None,
                        help="what the FRF is: " + ", ".join(sorted(FRF_UNITS)))


def read_mat(source: Path) -> dict[str, np.ndarray]:
    """Every numeric array of a ``.mat`` file by name (struct fields as ``s.field``).

    Raises
    ------
    RawDataError
        Not a MAT file, unreadable, or no numeric variable at all.
    """
    source = Path(source)
    if not source.is_file():
        raise RawDataError(source, "file does not exist", expected=WHAT)
    with open(source, "rb") as fh:
        head = fh.read(128)
    out: dict[str, np.ndarray] = {}
    if head[:8] == b"\x89HDF\r\n\x1a\n" or b"MATLAB 7.3" in head:
        out = _read_v73(source)
    else:
        import scipy.io

        try:
            raw = scipy.io.loadmat(str(source), squeeze_me=True)
        except Exception as exc:  # noqa: BLE001 - scipy raises several types on bad files
            raise RawDataError(source, f"not a readable MAT file ({type(exc).__name__}: "
                               f"{exc})", where="file", expected=WHAT) from None
        for name, v in raw.items():
            if name.startswith("__"):
                continue
            names = getattr(getattr(v, "dtype", None), "names", None)
            if names:  # a MATLAB struct: a numpy record, one array per field
                for fn in names:
                    field = v[fn]
                    if field.dtype == object and field.ndim == 0:
                        field = field.item()
                    _keep(out, f"{name}.{fn}", field)
            else:
                _keep(out, name, v)
    if not out:
        raise RawDataError(source, "no numeric variable", where="file",
                           expected="time records or FRFs as numeric arrays")
    return out


def _keep(out: dict, name: str, v) -> None:
    a = np.asarray(v)
    if a.dtype.kind in "fiuc" and a.size:
        out[name] = a


def _read_v73(source: Path) -> dict[str, np.ndarray]:
    import h5py

    out: dict[str, np.ndarray] = {}
    try:
        with h5py.File(source, "r") as h5:
            def visit(name, obj):
                if not isinstance(obj, h5py.Dataset) or name.startswith("#refs#"):
                    return
                a = obj[()]
                if a.dtype.names and {"real", "imag"} <= set(a.dtype.names):
                    a = a["real"] + 1j * a["imag"]
                a = np.asarray(a)
                if a.ndim >= 2:
                    a = a.T  # MATLAB stores column-major
                _keep(out, name.replace("/", "."), np.squeeze(a))
            h5.visititems(visit)
    except OSError as exc:
        raise RawDataError(source, f"not a readable MAT v7.3 (HDF5) file ({exc})",
                           where="file", expected=WHAT) from None
    return out


def _variables(variables: dict) -> str:
    return ", ".join(f"{k} {'x'.join(map(str, v.shape)) or 'scalar'}"
                     for k, v in list(variables.items())[:20])


def channel(source: Path, variables: dict, spec: ChannelSpec) -> np.ndarray:
    """The samples of one channel: ``(n,)`` or ``(n, pages)``."""
    name, col = spec.channel, None
    if m := _COLUMN.match(name):
        name, col = m[1], int(m[2])
    elif name.isdigit() and name not in variables:
        mats = [k for k, v in variables.items() if v.ndim >= 2 and min(v.shape[:2]) > 1]
        if len(mats) != 1:
            raise RawDataError(source, f"channel {spec.channel!r}: a column number needs one "
                               f"matrix, the file has {len(mats)}", where=f"option {spec.option}",
                               expected="NAME[column] (variables: " + _variables(variables) + ")")
        name, col = mats[0], int(spec.channel)
    if name not in variables:
        raise RawDataError(source, f"variable {name!r} is not in the file",
                           where=f"option {spec.option}",
                           expected="one of: " + _variables(variables))
    a = variables[name]
    if col is None:
        if a.ndim != 1:
            raise RawDataError(source, f"variable {name!r} is {'x'.join(map(str, a.shape))}",
                               where=f"option {spec.option}",
                               expected=f"a vector, or a column: {name}[1]")
        return a.astype(float)
    if a.ndim == 1 or a.ndim > 3:
        raise RawDataError(source, f"variable {name!r} is {'x'.join(map(str, a.shape))}",
                           where=f"option {spec.option}",
                           expected="a matrix of samples x channels (x records)")
    a = a if a.shape[0] >= a.shape[1] else np.swapaxes(a, 0, 1)  # samples along the long side
    if not 1 <= col <= a.shape[1]:
        raise RawDataError(source, f"column {col} of {name!r} ({a.shape[1]} channels)",
                           where=f"option {spec.option}", expected=f"1 … {a.shape[1]}")
    return np.real(a[:, col - 1]).astype(float)


def sampling_rate(source: Path, variables: dict, args) -> float:
    """``--fs-hz``, else a rate, a step or a time vector in the file."""
    if getattr(args, "fs_hz", None):
        return float(args.fs_hz)
    for name in RATE_NAMES:
        if name in variables and variables[name].size == 1:
            return nice_rate(float(variables[name]))
    for name in STEP_NAMES:
        if name in variables and variables[name].size == 1 and float(variables[name]) > 0:
            return nice_rate(1.0 / float(variables[name]))
    for name in TIME_NAMES:
        if name in variables and variables[name].ndim == 1 and variables[name].size > 2:
            d = np.diff(variables[name].astype(float))
            if np.all(d > 0) and np.ptp(d) <= 1e-3 * d.mean():
                return nice_rate(1.0 / d.mean())
    raise RawDataError(source, "no sampling rate", where="file",
                       expected="--fs-hz, or a variable " + ", ".join(RATE_NAMES + STEP_NAMES)
                                + " or a time vector t (variables: " + _variables(variables)
                                + ")")


def _convert_frf(src: Path, staging: Path, variables: dict, args) -> dict:
    import xarray as xr

    from robomill.modal.frf import to_receptance
    from robomill.modal.layout import frf_coords, parse_direction
    from robomill.modal.uff import write_frf_uff

    unit = (getattr(args, "frf_unit", None) or "").strip().lower().replace(" ", "")
    if unit not in FRF_UNITS:
        raise RawDataError(src, "FRF unit not stated" if not unit
                           else f"FRF unit {args.frf_unit!r}", where="option --frf-unit",
                           expected="one of " + ", ".join(sorted(FRF_UNITS)))
    form, factor = FRF_UNITS[unit]
    for opt in ("frf", "freq"):
        if getattr(args, opt, None) not in variables:
            raise RawDataError(src, f"variable {getattr(args, opt, None)!r} is not in the file"
                               if getattr(args, opt, None) else f"no --{opt}",
                               where=f"option --{opt}", expected="one of: "
                               + _variables(variables))
    f = np.asarray(variables[args.freq], float).ravel()
    H = np.asarray(variables[args.frf])
    H = H.reshape(-1, 1) if H.ndim == 1 else (H if H.shape[0] == f.size else H.T)
    if H.ndim != 2 or H.shape[0] != f.size:
        raise RawDataError(src, f"FRF {args.frf!r} is {'x'.join(map(str, H.shape))}, the "
                           f"frequency vector has {f.size} lines", where="option --frf",
                           expected="frequencies x responses")
    if np.any(np.diff(f) <= 0) or np.ptp(np.diff(f)) > 1e-6 * np.mean(np.diff(f)):
        raise RawDataError(src, "frequency lines are not uniform", where="option --freq",
                           expected="a uniform frequency axis")
    coh = None
    if getattr(args, "coherence", None):
        if args.coherence not in variables:
            raise RawDataError(src, f"variable {args.coherence!r} is not in the file",
                               where="option --coherence",
                               expected="one of: " + _variables(variables))
        coh = np.real(np.asarray(variables[args.coherence], float))
        coh = coh.reshape(-1, 1) if coh.ndim == 1 else (coh if coh.shape[0] == f.size
                                                        else coh.T)
        if coh.shape != H.shape:
            raise RawDataError(src, f"coherence is {'x'.join(map(str, coh.shape))}, the FRF "
                               f"{'x'.join(map(str, H.shape))}", where="option --coherence",
                               expected="the FRF's shape")
    specs = [parse_response(r, src) for r in getattr(args, "response", []) or []]
    if len(specs) != H.shape[1]:
        raise RawDataError(src, f"{len(specs)} --response for {H.shape[1]} FRF column(s)",
                           where="option --response",
                           expected="one --response COLUMN:DIRECTION per column")
    cols = []
    for s in specs:
        if not s.channel.isdigit() or not 1 <= int(s.channel) <= H.shape[1]:
            raise RawDataError(src, f"--response {s.channel}:{s.direction}: not a column",
                               where="option --response", expected=f"1 … {H.shape[1]}")
        cols.append(int(s.channel) - 1)
    ref = (int(getattr(args, "node", 1) or 1),
           parse_direction(hammer_direction(src, getattr(args, "direction", None))))
    outs = [(s.node, parse_direction(s.direction)) for s in specs]
    if len(set(outs)) != len(outs):
        raise RawDataError(src, "two columns measure the same point", where="option --response",
                           expected="one column per point")
    Hx = to_receptance(H[:, cols].T * factor, f, form)[:, None, :]
    data = {"H": (("output", "input", "frequency"), Hx, {"units": "m/N"})}
    if coh is not None:
        data["coherence"] = (("output", "input", "frequency"), coh[:, cols].T[:, None, :],
                             {"units": "1"})
    ds = xr.Dataset(data, coords=frf_coords(f, outs, [ref]))
    rel = f"impact/{safe_stem(src)}.uff"
    (staging / "impact").mkdir(parents=True, exist_ok=True)
    write_frf_uff(ds, staging / rel)
    return {"path": rel, "kind": "impact", "uff_content": "frf", "source_file": src.name,
            "source_format": "mat", "frf_form": form, "frf_unit": args.frf_unit}


def convert(sources: list[Path], staging: Path, args: argparse.Namespace) -> list[dict]:
    """Write the hit CSVs (or the FRF file) of every source; return their entries."""
    entries: list[dict] = []
    for src in map(Path, sources):
        variables = read_mat(src)
        if getattr(args, "frf", None):
            entries.append(_convert_frf(src, staging, variables, args))
            continue
        if not getattr(args, "hammer", None):
            raise RawDataError(src, "no --hammer (time records) and no --frf (an analyser's "
                               "FRFs)", where="options",
                               expected="--hammer VAR[:unit] --response VAR:DIR[:unit], or "
                                        "--frf VAR --freq VAR (variables: "
                                        + _variables(variables) + ")")
        hammer = parse_hammer(getattr(args, "hammer", None), src)
        specs = [parse_response(r, src) for r in getattr(args, "response", []) or []]
        if not specs:
            raise RawDataError(src, "no response channel given", where="option --response",
                               expected="--response CHANNEL:DIRECTION[:unit] (repeatable), "
                                        "or --frf for an analyser's FRFs (variables: "
                                        + _variables(variables) + ")")
        fs = sampling_rate(src, variables, args)
        f_scale, f_origin = scale_to_si(src, hammer, None, force=True)
        force = channel(src, variables, hammer) * f_scale
        resp, units = [], {hammer.channel: f_origin}
        for s in specs:
            scale, origin = scale_to_si(src, s, None, force=False)
            a = channel(src, variables, s) * scale
            if a.shape != force.shape:
                raise RawDataError(src, f"channel {s.channel!r} has shape {a.shape}, the "
                                   f"hammer {force.shape}", where="option --response",
                                   expected="channels recorded together")
            resp.append((s, a))
            units[s.channel] = origin
        pages = 1 if force.ndim == 1 else force.shape[1]
        stem = safe_stem(src)
        own: list[dict] = []
        for p in range(pages):
            fp = force if force.ndim == 1 else force[:, p]
            rp = [(s, a if a.ndim == 1 else a[:, p]) for s, a in resp]
            got = write_hits(src, staging, stem if pages == 1 else f"{stem}_r{p + 1}", fs, fp,
                             rp, args, {"source_file": src.name, "source_format": "mat",
                                        "units": units})
            append_hits(own, got)  # hit numbers go on through the file's records
        entries.extend(own)
    return finish_hits(staging, entries)
