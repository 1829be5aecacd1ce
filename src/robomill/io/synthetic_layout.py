"""The layout of the synthetic study's raw folder: which raw files the instrument simulators
write, as a manifest (without sha256), computed from the configuration alone.

Snakemake plans its DAG from here at every start (``workflow/rules/common.smk``), so this
module imports no simulator (the simulators import it; :mod:`robomill.synth.truth` imports
them): :func:`instrument_files` lays out each instrument's files, and the layout goes
through the same parser as a real folder's ``manifest.yaml``
(:func:`robomill.io.manifest.parse_manifest` with ``require_sha256=False``): cuts and files
come from one place in both modes.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

from robomill.experiment import Cut, plan_cuts, tracker_run_id
from robomill.settings import config_section

SIMULATORS = ("profilometer", "dynamometer", "tracker", "impact", "ctrack", "loadtests",
              "recordings")
"""The seven simulator modules of :mod:`robomill.synth` (none imported by planning)."""

CTRACK_TABLES = ("circles", "home", "steps", "base", "loads", "accuracy")
"""The C-Track tables of the calibration protocol (one file each)."""

IMPACT_DIRECTIONS = ("X", "Y", "Z")
"""Impact hit directions (base axes)."""


def _settings(config: Mapping[str, Any], instrument: str) -> dict[str, Any]:
    """``synth.<instrument>``, the schema's defaults filled
    (:func:`robomill.settings.config_section`)."""
    return config_section(config, f"synth.{instrument}")


def synthetic_cuts(config: Mapping[str, Any]) -> list[Cut]:
    """The cuts of the virtual study: ``experiment.cuts`` when given (a design of any kind,
    parsed by the manifest's own cut parser), else ``experiment.sets`` cycled to
    ``synth.sets`` sets (the thesis design).

    Raises
    ------
    ConfigError
        A cut the simulators cannot make: off the thesis layout without ``start_mm``. Cuts
        of any radial immersion and milling mode are simulated with their own chip model
        (:func:`robomill.forces.engagement_angles_rad`).
    """
    exp = config["experiment"]
    if not exp.get("cuts"):
        return plan_cuts(exp["sets"], int(config["synth"]["sets"]), exp["directions"])
    from robomill.errors import ConfigError, RawDataError
    from robomill.io.manifest import parse_manifest

    header = experiment_header(config)
    try:
        cuts = parse_manifest({"experiment": header, "cuts": list(exp["cuts"]), "files": []},
                              "config.yaml: experiment").cuts
    except RawDataError as err:
        raise ConfigError(f"config key 'experiment.cuts': {err.where}: {err.problem}"
                          + (f" (expected {err.expected})" if err.expected else "")) from None
    for i, c in enumerate(cuts):
        on_layout = c.set is not None and c.segment is not None and c.direction in (
            "px", "py", "my")
        if c.start_mm is None and not on_layout:
            raise ConfigError(f"config key 'experiment.cuts[{i}]': cut {c.id!r} needs start_mm "
                              "(or set, segment and a direction px/py/my of the thesis layout)")
    return cuts


def experiment_header(config: Mapping[str, Any]) -> dict[str, Any]:
    """The manifest's ``experiment`` mapping from the configuration."""
    exp = config["experiment"]
    header = {k: exp[k] for k in ("spindle_rpm", "flutes", "tool_diameter_mm", "cut_length_mm")}
    if exp.get("modal_band_hz") is not None:  # the design's modal band of interest
        header["modal_band_hz"] = [float(b) for b in exp["modal_band_hz"]]
    return header


def impact_tcp_mm(config: Mapping[str, Any]) -> list[float]:
    """The TCP point [mm, base frame] at which the virtual impact test is made, as its
    manifest entries state it (``tcp_mm``): ``synth.process.reference_point_mm`` (a choice of
    the test, like a lab's: where the tool stood when it was hit), null: the mean of the
    midpoints of the study's cuts."""
    point = (config["synth"].get("process") or {}).get("reference_point_mm")
    if point is None:
        import numpy as np

        from robomill.experiment import cut_endpoints_mm

        cuts = synthetic_cuts(config)
        point = np.mean([np.mean(cut_endpoints_mm(c, config["experiment"]), axis=0)
                         for c in cuts], axis=0)
    return [float(v) for v in point]


def hit_path(direction: str, hit: int) -> str:
    """Path of one impact hit's file, relative to the raw folder."""
    return f"impact/hit{direction}_{hit}.csv"


def tracker_runs(config: Mapping[str, Any]) -> list[dict[str, Any]]:
    """The tracker runs: one per (direction, feed) of the experiment (``synth.tracker``
    ``directions``/``feeds_mm_s`` select; null = all), each following the path of the last
    cut with that direction and feed; with ``synth.tracker.per_cut`` one per tracked cut, its
    id the cut's. With ``synth.tracker.air_pass`` each run twice: ``pass`` ``loaded`` and
    ``air`` (run id ``<run>_air``), the same path without material. Keys ``run, direction,
    feed_mm_s, cut`` (a :class:`Cut`; ``per_cut`` True where the manifest carries the run id;
    ``pass`` with ``air_pass``)."""
    exp = config["experiment"]
    tr = _settings(config, "tracker")
    dirs = tr["directions"] or list(exp.get("directions") or ("py", "px", "my", "mx"))
    feeds = tr["feeds_mm_s"]
    tracked = [c for c in synthetic_cuts(config)  # cuts by direction_deg only: no run
               if c.direction in dirs and (feeds is None or any(
                   math.isclose(c.feed_mm_s, f, rel_tol=1e-5, abs_tol=1e-8) for f in feeds))]
    if tr.get("per_cut"):  # one run per cut, keyed by the cut's id (manifest key run)
        runs = [{"run": c.id, "direction": c.direction, "feed_mm_s": c.feed_mm_s, "cut": c,
                 "per_cut": True} for c in tracked]
    else:
        chosen: dict[tuple[str, float], Cut] = {}
        for c in tracked:
            chosen[(c.direction, c.feed_mm_s)] = c
        runs = []
        for d in dirs:
            for (dd, feed), c in sorted(chosen.items(), key=lambda kv: kv[0][1]):
                if dd == d:
                    runs.append({"run": tracker_run_id(d, feed), "direction": d,
                                 "feed_mm_s": feed, "cut": c})
    if not tr.get("air_pass"):
        return runs
    # each run twice: loaded (while cutting) and air (the same path without material)
    return [p for r in runs for p in ({**r, "pass": "loaded"},
                                      {**r, "run": f"{r['run']}_air", "pass": "air",
                                       "per_cut": True})]


def loadtest_robots(config: Mapping[str, Any]) -> list[str]:
    """Names of the robots of the simulated load tests (``synth.loadtests.robots``)."""
    return [str(e["name"]) for e in (config["synth"].get("loadtests") or {}).get("robots", [])]


def instrument_files(config: Mapping[str, Any], instrument: str) -> list[dict[str, Any]]:
    """The raw files (path, kind, metadata) one simulator writes."""
    if instrument == "profilometer":
        return [{"path": f"profiles/{c.id}.csv", "kind": "profile", "cut": c.id}
                for c in synthetic_cuts(config)]
    if instrument == "dynamometer":
        s = _settings(config, "dynamometer")
        return [{"path": f"forces/{c.id}.{s['format']}", "kind": "force", "cut": c.id,
                 "fs_hz": float(s["fs_hz"])} for c in synthetic_cuts(config)]
    if instrument == "tracker":
        fs = float(_settings(config, "tracker")["fs_hz"])
        return [{"path": f"tracker/{r['run']}.csv", "kind": "tracker",
                 "direction": r["direction"], "feed_mm_s": float(r["feed_mm_s"]),
                 "fs_hz": fs, "cut": r["cut"].id, **({"run": r["run"]} if r.get("per_cut")
                                                      else {}),
                 **({"pass": r["pass"]} if "pass" in r else {})}
                for r in tracker_runs(config)]
    if instrument == "impact":
        if "impact" not in config["synth"]:
            return []
        s = _settings(config, "impact")
        n = int(s["hits_per_direction"])
        # the simulated sensors' ranges, as a lab states them in its manifest
        ranges = {"range_N": float(s["force_range_N"]), "range_ms2": float(s["accel_range_ms2"])}
        # where the tool stood when it was hit, as a lab notes the test's pose
        tcp = impact_tcp_mm(config) if "process" in config["synth"] else None
        return [{"path": hit_path(d, k), "kind": "impact", "direction": d, "hit": k, **ranges,
                 **({"tcp_mm": list(tcp)} if tcp is not None else {})}
                for d in IMPACT_DIRECTIONS for k in range(1, n + 1)]
    if instrument == "ctrack":
        return [{"path": f"ctrack/{t}.csv", "kind": "ctrack", "table": t} for t in CTRACK_TABLES]
    if instrument == "loadtests":
        files = []
        for name in loadtest_robots(config):
            files.append({"path": f"stiffness/{name}.yaml", "kind": "robot", "robot": name})
            files.append({"path": f"stiffness/load_tests_{name}.csv", "kind": "stiffness",
                          "robot": name})
        return files
    if instrument == "recordings":  # microphone and spindle accelerometer: off by default
        s = _settings(config, "recordings")
        files = []
        for c in synthetic_cuts(config):
            # the cut's recordings, then their air passes (the same path without material)
            for p in ("", "_air") if s["air_pass"] else ("",):
                air = {"pass": "air"} if p else {}
                if s["sound"]:
                    files.append({"path": f"sound/{c.id}{p}.wav", "kind": "sound",
                                  "cut": c.id, **air})
                if s["vibration"]:
                    files.append({"path": f"vibration/{c.id}{p}.csv", "kind": "vibration",
                                  "cut": c.id, "fs_hz": float(s["accel_fs_hz"]), **air})
        return files
    raise ValueError(f"unknown instrument {instrument!r} (one of {', '.join(SIMULATORS)})")


def planned_files(config: Mapping[str, Any]) -> list[dict[str, Any]]:
    """Every synthetic raw file (path relative to the raw folder, kind, metadata): each
    instrument's files, then the cell file ``cell.yaml`` (written from ``config.yaml: cell``;
    last, so that the manifest and ``results/ingest/files.csv`` of the thesis study keep their
    order and columns, with one row more)."""
    files: list[dict[str, Any]] = []
    for instrument in SIMULATORS:
        files.extend(instrument_files(config, instrument))
    files.append({"path": "cell.yaml", "kind": "cell"})
    return files


def synthetic_manifest(config: Mapping[str, Any]) -> dict[str, Any]:
    """The synthetic study as a manifest mapping without sha256 (``experiment``, ``cuts``,
    ``files``): what :func:`robomill.io.manifest.parse_manifest` reads in both modes."""
    return {"experiment": experiment_header(config),
            "cuts": [c.as_dict() for c in synthetic_cuts(config)],
            "files": planned_files(config)}

