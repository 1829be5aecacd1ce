"""Modal results written as universal files: the FRFs as UFF 58 (with the node numbers and
direction codes of every point) and the identified modes as UFF 15 nodes + UFF 55 complex
mode shapes, both read back by pyuff and by modal test software."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np
import xarray as xr

from robomill.modal.layout import points


def write_frf_uff(ds: xr.Dataset, path: str | Path) -> Path:
    """Write ``H`` (complex, m/N; receptance codes 8/13) and ``coherence`` of an FRF dataset
    as UFF 58 sets with the node numbers and direction codes of every point; pairs the layout
    did not measure are left out.

    Frequency lines must be uniform; the DC line is written as 0 where it is NaN.
    """
    import pyuff

    from robomill.io.atomic import atomic_path

    f = ds["frequency"].values
    df = float(f[1] - f[0])
    outs, ins = points(ds, "output"), points(ds, "input")
    sets = []
    for a, o in enumerate(ds["output"].values):
        for b, i in enumerate(ds["input"].values):
            h = ds["H"].sel(output=o, input=i).values
            if not np.isfinite(h[f > 0]).any():
                continue
            h = np.nan_to_num(h)
            common = dict(rsp_node=outs[a][0], rsp_dir=outs[a][1], ref_node=ins[b][0],
                          ref_dir=ins[b][1], abscissa_spacing=1, abscissa_min=float(f[0]),
                          abscissa_inc=df, abscissa_spec_data_type=18, x=f, id2="robomill",
                          id3="", id4="", id5="", rsp_ent_name="tooltip", ref_ent_name="tooltip")
            sets.append(pyuff.prepare_58(func_type=4, id1=f"H {o}/{i} receptance m/N",
                                         ordinate_spec_data_type=8,
                                         orddenom_spec_data_type=13, data=h.astype(complex),
                                         **common))
            if "coherence" in ds:
                coh = np.nan_to_num(ds["coherence"].sel(output=o, input=i).values)
                sets.append(pyuff.prepare_58(func_type=6, id1=f"coherence {o}/{i}",
                                             ordinate_spec_data_type=0,
                                             orddenom_spec_data_type=0,
                                             data=coh.astype(float), **common))
    with atomic_path(path) as tmp:
        pyuff.UFF(str(tmp)).write_sets(sets, mode="overwrite")
    return Path(path)


def write_modes_uff(modes, shapes, path: str | Path, *,
                    node_xyz_m: Mapping[int, Sequence[float]] | None = None) -> Path:
    """Write the identified modes as UFF 15 (nodes) + UFF 55 (one complex mode shape per
    mode, translations r1…r3 = X, Y, Z at each node) that pyuff reads back.

    Parameters
    ----------
    modes
        The mode table (:data:`robomill.modal.MODE_COLUMNS`: ``f_n_hz``, ``zeta``,
        ``m_modal_kg``).
    shapes
        :class:`robomill.modal.ModeShapes`; a component measured along a negative axis is
        stored with its sign turned to the positive axis; axes not measured are 0.
    node_xyz_m
        Node coordinates; without them node k sits at x = (k − 1) × 0.1 m (the test
        gave no geometry: the UFF 15 set then only names the nodes).
    """
    import pyuff

    from robomill.io.atomic import atomic_path

    nodes = sorted({n for n, _ in shapes.points})
    xyz = np.array([node_xyz_m[n] if node_xyz_m and n in node_xyz_m
                    else ((n - 1) * 0.1, 0.0, 0.0) for n in nodes], float)
    ids = np.array(nodes, int)
    sets = [pyuff.prepare_15(node_nums=ids, def_cs=np.zeros(len(nodes), int),
                             disp_cs=np.zeros(len(nodes), int), color=np.ones(len(nodes), int),
                             x=xyz[:, 0], y=xyz[:, 1], z=xyz[:, 2])]
    for r, row in enumerate(modes.itertuples(index=False)):
        comp = np.zeros((len(nodes), 3), complex)
        for k, (n, d) in enumerate(shapes.points):
            v = shapes.shapes[r, k]
            comp[nodes.index(n), abs(d) - 1] = np.sign(d) * (0 if not np.isfinite(v) else v)
        f, z = float(row.f_n_hz), float(row.zeta)
        wn = 2 * np.pi * f
        eig = complex(-z * wn, wn * np.sqrt(max(0.0, 1 - z * z)))
        m = float(row.m_modal_kg) if np.isfinite(row.m_modal_kg) else 0.0
        sets.append(pyuff.prepare_55(
            id1=f"mode {int(row.mode)}: {f:.4f} Hz, zeta {z:.5f}", id2="robomill",
            id3="complex unit shape over the measured points", id4="", id5="",
            model_type=1, analysis_type=3, data_ch=2, spec_data_type=8, data_type=5,
            n_data_per_node=3, r1=comp[:, 0], r2=comp[:, 1], r3=comp[:, 2], load_case=1,
            mode_n=int(row.mode), eig=eig, modal_a=complex(m, 0.0), modal_b=0j,
            node_nums=ids))
    with atomic_path(path) as tmp:
        pyuff.UFF(str(tmp)).write_sets(sets, mode="overwrite")
    return Path(path)


