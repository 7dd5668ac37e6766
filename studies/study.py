"""Parameter studies of Willert, Machines 11 (2023) 484 (Figs. 4-9) with the apparatus model.

``python -m mdr study fig8 --out DIR``: slip index against the flat-face radius b
(1 um - 1 mm, log scale) for k_x = 1, 2, 10, 20 N/um, with the flat punch of
radius b beside it. ``fig9``: slip index against k_x for b = 10, 50, 100 um.
``loops``: the four experiment cases of Figs. 4-7 (loop plots F_x-F_N, F_x-du).
``sensitivity``: slip index at the Table 2 point as each reconstructed quantity
(bedding radius, mu2, plate model, bedding on/off, dF, alpha) varies one at a
time (CSV + markdown table). ``plates``: every reading of the brass plates
(``mdr.apparatus``, A3) against the paper's points of Figs. 4-9 (CSV + markdown
table). fig8, fig9 and loops take ``--plate-model`` and ``--R-bed``.
Table 2 values: F0 = 0.5 N, dF = 0.1 N, mu1 = 0.2, mu2 = 0.1, u_A = 150 nm.
All points of a study run as one batch (one pass of the vectorised laws).
Study resolution: 100 spring cells, 120 steps per cycle, 3 cycles (the slip
index changes by < 1e-3 against 400 cells / 400 steps).

Layout: this module runs the studies and writes their files (``run_study``, ``run_studies``); the
studies themselves are in ``studies.paper`` (fig8, fig9, loops, sensitivity) and
``studies.plates`` (plates), whose names are importable from here.
"""
from __future__ import annotations

import csv
import io
import time
from pathlib import Path

import numpy as np

from mdr.apparatus import Apparatus
from common.errors import InputError
from common.io import dumps_json, write_bytes_atomic

from .paper import (LOOP_CASES, LOOP_RES, R_IND, RES, SENS_BASE, SENS_POINTS, SENS_VARY, TABLE1_B, TABLE1_KX,
                    TABLE2, fig8, fig9, loops, sensitivity, sensitivity_markdown)
from .paper import _slip_index  # noqa: F401 (tests and benchmarks import it from here)
from .plates import FX_COMPLIANCE_ROWS, PAPER_POINTS, PLATE_READINGS, PLATES_RES, plate_readings, plates_markdown

__all__ = ["APP_KW_STUDIES", "CSV_UNITS", "FX_COMPLIANCE_ROWS", "LOOP_CASES", "LOOP_RES", "PAPER_POINTS",
           "PLATES_RES", "PLATE_READINGS", "RES", "R_IND", "SENS_BASE", "SENS_POINTS", "SENS_VARY", "STUDIES",
           "TABLE1_B", "TABLE1_KX", "TABLE2", "fig8", "fig9", "loops", "plate_readings", "plates_markdown",
           "run_studies", "run_study", "sensitivity", "sensitivity_markdown", "study_names", "study_outputs"]


#: the units of the study rows' dimensional columns, written into the CSV headers (SI)
CSV_UNITS = {"kx": "N/m", "b": "m"}


def _csv(rows):
    """The rows as CSV, a dimensional column's header carrying its unit (``CSV_UNITS``): ``kx (N/m)``."""
    buf = io.StringIO()
    keys = list(rows[0])
    buf.write(",".join(f"{k} ({CSV_UNITS[k]})" if k in CSV_UNITS else k for k in keys) + "\r\n")
    w = csv.DictWriter(buf, fieldnames=keys)
    w.writerows(rows)
    return buf.getvalue().encode()


def _png(fig) -> bytes:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=120)
    return buf.getvalue()


STUDIES = ("fig8", "fig9", "loops", "sensitivity", "plates")
APP_KW_STUDIES = ("fig8", "fig9", "loops")  # the studies that take one apparatus (app_kw)


def run_study(name: str, out_dir, app_kw=None) -> dict:
    """Run study ``name`` (fig8, fig9, loops, sensitivity, plates) and write CSV/JSON + PNG
    (sensitivity, plates: CSV + markdown table) into out_dir. ``app_kw``: Apparatus fields
    (plate_model, R_bed) for fig8, fig9 and loops (the other two vary them themselves)."""
    res, files = study_outputs(name, app_kw)
    _write_files(out_dir, files)
    return res


def _write_files(out_dir, files: dict) -> None:
    for fname, data in files.items():
        write_bytes_atomic(Path(out_dir) / fname, data)


def study_outputs(name: str, app_kw=None) -> tuple[dict, dict]:
    """Run study ``name`` (``app_kw`` as :func:`run_study`); returns its result {study, rows,
    runtime_s, worker} and its files {file name: bytes} (written by the caller: a remote
    worker needs no shared disk)."""
    if app_kw and name not in APP_KW_STUDIES:
        raise InputError(f"plate_model/R_bed apply to the studies {', '.join(APP_KW_STUDIES)}, not to {name}")
    if app_kw:
        Apparatus(**app_kw)  # checked before the work
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from common.executors import worker_id

    files, fig = {}, None
    t0 = time.perf_counter()
    if name == "fig8":
        rows = fig8(app_kw=app_kw)
        files["fig8.csv"] = _csv(rows)
        fig, ax = plt.subplots(figsize=(6, 4))
        for kx in sorted({r["kx"] for r in rows}):
            sel = [r for r in rows if r["kx"] == kx]
            line, = ax.semilogx([r["b"] * 1e6 for r in sel], [r["slip_index_truncated"] for r in sel], lw=2,
                                label=f"k_x = {kx / 1e6:g} N/um")
            ax.semilogx([r["b"] * 1e6 for r in sel], [r["slip_index_flat"] for r in sel], lw=0.8, color=line.get_color())
        ax.set_xlabel("flat-face radius b (um)")
        ax.set_ylabel("slip index delta = dW / (4 mu1 u_A F0)")
        ax.set_title("Fig. 8: truncated sphere R = 6 mm (thick) and flat punch of radius b (thin)\n"
                     "F0 = 0.5 N, dF = 0.1 N, u_A = 150 nm, mu1 = 0.2, mu2 = 0.1", fontsize=9)
        ax.legend()
        fig.tight_layout()
        files["fig8.png"] = _png(fig)
    elif name == "fig9":
        rows = fig9(app_kw=app_kw)
        files["fig9.csv"] = _csv(rows)
        fig, ax = plt.subplots(figsize=(6, 4))
        for b in sorted({r["b"] for r in rows}):
            sel = [r for r in rows if r["b"] == b]
            ax.semilogx([r["kx"] / 1e6 for r in sel], [r["slip_index_truncated"] for r in sel], label=f"b = {b * 1e6:g} um")
        ax.axvline(0.2 * 0.5 / 150e-9 / 1e6, color="k", ls=":", label="mu1 F0 / u_A")
        ax.set_xlabel("apparatus stiffness k_x (N/um)")
        ax.set_ylabel("slip index delta = dW / (4 mu1 u_A F0)")
        ax.set_title("Fig. 9: truncated spheres R = 6 mm in the apparatus\n"
                     "F0 = 0.5 N, dF = 0.1 N, u_A = 150 nm, mu1 = 0.2, mu2 = 0.1", fontsize=9)
        ax.legend()
        fig.tight_layout()
        files["fig9.png"] = _png(fig)
    elif name == "loops":
        data = loops(app_kw=app_kw)
        files["loops.json"] = dumps_json(data).encode()
        fig, axes = plt.subplots(len(data), 2, figsize=(8, 2.6 * len(data)))
        for i, (row, (key, d)) in enumerate(zip(axes, data.items())):
            row[0].plot(np.asarray(d["FN"]), np.asarray(d["Fx"]) * 1e3, "r", label="MDR, smooth indenter")
            row[0].set_xlabel("F_N (N)")
            row[0].set_ylabel("F_x (mN)")
            if i == 0:  # one curve per panel, the same model throughout
                row[0].legend(fontsize=7, loc="upper left")
            row[1].plot(np.asarray(d["du"]) * 1e9, np.asarray(d["Fx"]) * 1e3, "r")
            row[1].set_xlabel("du = u_2 - u_1 (nm), the contact's slip")
            row[0].set_title(f"{key}: {d['profile']} F0 = {d['F0']} N, u_A = {d['ua'] * 1e9:g} nm, "
                             f"delta = {d['slip_index']:.2f}, on limit {100 * d['on_limit']:.0f} %",
                             fontsize=8, loc="left")
        fig.tight_layout()
        files["loops.png"] = _png(fig)
        rows = [{k: v for k, v in d.items() if k not in ("Fx", "FN", "du")} | {"case": k} for k, d in data.items()]
    elif name == "sensitivity":
        rows = sensitivity()
        files["sensitivity.csv"] = _csv(rows)
        files["sensitivity.md"] = sensitivity_markdown(rows).encode()
    elif name == "plates":
        rows = plate_readings()
        files["plates.csv"] = _csv(rows)
        files["plates.md"] = plates_markdown(rows).encode()
    else:
        raise InputError(f"study must be one of {', '.join(STUDIES)}; got {name!r}")
    if fig is not None:
        plt.close(fig)
    return {"study": name, "rows": rows, "runtime_s": time.perf_counter() - t0, "worker": worker_id()}, files


def study_names(names) -> list:
    """Validated list of study names from a comma list (or iterable); 'all' = every study."""
    if isinstance(names, str):
        names = [n.strip() for n in names.split(",") if n.strip()]
    names = list(dict.fromkeys(STUDIES if list(names) == ["all"] else names))
    bad = [n for n in names if n not in STUDIES]
    if bad or not names:
        raise InputError(f"study must be one of {', '.join(STUDIES)} (or a comma list, or all); got {', '.join(bad) or 'nothing'}")
    return names


def run_studies(names, out_dir, jobs: int = 1, app_kw=None, scheduler: str | None = None, *, law: str = "mdr",
                plugin=None, law_args=None, points=None, levels=None, log=None) -> list:
    """Run several studies, each one batch pass, in up to ``jobs`` spawned processes or on
    the workers of the Dask scheduler at ``scheduler`` (``common.executors``).

    The studies are independent and each is already one batch pass over its points,
    so the second core is used by running two studies at once. With the compiled loops
    (``mdr.kernels``) a study takes about a second and starting a worker (imports,
    loading the compiled code) costs more: ``jobs`` pays only without numba. The files
    are written here as each study comes back. Each result names its ``worker`` and the
    ``executor`` of the run. ``app_kw``: Apparatus fields for fig8, fig9, loops.

    ``law`` other than "mdr": fig8/fig9 with that plugin law (``plugin``, its parsed flags
    ``law_args``) beside MDR at ``points`` points per curve on ``levels`` mesh levels
    (``studies.law_study``); its (geometry, level) tasks are what the processes or workers share.
    """
    from common.executors import check_choice, executor_for

    names = study_names(names)
    jobs = check_choice(jobs, scheduler)
    bad = [n for n in names if app_kw and n not in APP_KW_STUDIES]
    if bad:
        raise InputError(f"--plate-model/--R-bed apply to the studies {', '.join(APP_KW_STUDIES)}, not to {', '.join(bad)}")
    if law != "mdr":
        if app_kw:
            raise InputError("--plate-model/--R-bed do not apply with --law (the FE-backed studies use the default apparatus)")
        return _run_law_studies(names, out_dir, jobs, scheduler, law, plugin, law_args, points, levels, log)
    if scheduler is None and (jobs == 1 or len(names) == 1):
        jobs = 1
    res = {}
    with executor_for(min(jobs, len(names)), scheduler) as (ex, label):
        if ex is None:
            for n in names:
                res[n], files = study_outputs(n, app_kw)
                _write_files(out_dir, files)
        else:
            # longest first, so that the pool balances (fig8 holds two batches)
            futs = {n: ex.submit(study_outputs, n, app_kw) for n in sorted(names, key=STUDIES.index)}
            for n, f in futs.items():
                res[n], files = f.result()
                _write_files(out_dir, files)
    return [dict(res[n], executor=label) for n in names]


def _run_law_studies(names, out_dir, jobs, scheduler, law, plugin, law_args, points, levels, log) -> list:
    """fig8/fig9 with a plugin law beside MDR (``studies.law_study``): CSV + PNG ``NAME_LAW.*``."""
    from common.executors import executor_for
    from .law_study import DEFAULT_LEVELS, DEFAULT_POINTS, LAW_STUDIES, check_law_study, law_figure, law_study

    bad = [n for n in names if n not in LAW_STUDIES]
    if bad:
        raise InputError(f"study with --law {law} must be one of {', '.join(LAW_STUDIES)}; got {', '.join(bad)}")
    if plugin is None:
        raise InputError(f"law must be mdr or an installed contact-law plugin; got {law!r}")
    points, levels = check_law_study(law, plugin, DEFAULT_POINTS if points is None else points,
                                     DEFAULT_LEVELS if levels is None else levels)
    out = []
    with executor_for(jobs, scheduler) as (ex, label):
        for n in names:
            t0 = time.perf_counter()
            mdr_rows = fig8() if n == "fig8" else fig9()
            rows, tasks = law_study(n, mdr_rows, law, plugin, law_args, R=R_IND, load=TABLE2, res=RES,
                                    points=points, levels=levels, executor=ex, log=log)
            fig = law_figure(n, mdr_rows, rows, law)
            _write_files(out_dir, {f"{n}_{law}.csv": _csv(rows), f"{n}_{law}.png": _png(fig)})
            import matplotlib.pyplot as plt

            plt.close(fig)
            out.append({"study": n, "law": law, "rows": rows, "tasks": tasks, "runtime_s": time.perf_counter() - t0,
                        "worker": ", ".join(sorted({t["worker"] for t in tasks})), "executor": label})
    return out
