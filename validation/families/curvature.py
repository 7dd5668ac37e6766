"""The family ``curvature``: the contact radius a/R swept (and the Poisson ratio), MDR against the FE
model on their full ladders per variant, so that the curvature effect (FE extrapolated minus MDR) stands
with its error bar beside the tolerance (the parabolic profile is exact only as a/R -> 0).
"""
from __future__ import annotations

import time
from dataclasses import dataclass, replace
from pathlib import Path

from common.errors import InputError

from mdr.materials import Materials

from .. import metrics
from . import number, result_of, variant_keys
from ..scenes import Scene
from ..sides import run_fe, run_mdr
from ..text import LABELS, grade_text, num
from .pair import scene_verdicts

#: the key of the family's rows in a result, and the title of its figure in the report
KEY = 'curvature'
TITLE = 'curvature'


#: the contact radius over R a variant may load the sphere to (the cap is at most R high: 20 a at 5 %)
A_OVER_R_MAX = 0.1


@dataclass(frozen=True)
class Variant:
    """One variant of a curvature scene: the sphere loaded to the contact radius a = ``a_over_R`` R, both
    bodies of Poisson ratio ``nu`` (None: the scene's nu1)."""

    a_over_R: float
    nu: float | None = None

    @classmethod
    def of(cls, v: dict, scene: Scene) -> "Variant":
        """The mapping ``v`` checked: ``a_over_R`` in (0, 0.1], optionally ``nu`` in (-1, 0.5)."""
        bad = variant_keys(scene, "curvature", v, ("a_over_R", "nu"))
        if scene.profile != "sphere":
            raise InputError(f"scene {scene.name}: curvature variants need profile 'sphere', got {scene.profile!r}")
        x = number(v, "a_over_R", lambda x: 0 < x <= A_OVER_R_MAX, bad, f"in (0, {A_OVER_R_MAX:g}]")
        nu = number(v, "nu", lambda x: -1 < x < 0.5, bad, "in (-1, 0.5)") if "nu" in v else None
        return cls(x, nu)

    def scene(self, s: Scene) -> Scene:
        """The sphere of scene ``s`` loaded to this contact radius (Hertz: F0 = 4 E* a^3 / (3 R)), both
        bodies of Poisson ratio ``nu``, force amplitude mu F0 / 2, a pair scene.

        For the parabolic profile only a/R matters, and the FE body's shape in units of a is
        the same for a given a/R whether F0 or R is varied; the sphere's cap is at most R high
        (20 a at a/R = 5 %), so at large a/R the real sphere is also a small body."""
        nu = s.nu1 if self.nu is None else self.nu
        E_star = Materials(s.E1, nu, s.E2, nu).E_star
        a = self.a_over_R * s.R
        F0 = 4.0 * E_star * a ** 3 / (3.0 * s.R)
        return replace(s, name=f"{s.name}[a/R={self.a_over_R:g},nu={nu:g}]", F0=F0, dF=0.0,
                       amplitude=0.5 * s.mu * F0, nu1=nu, nu2=nu, variants=(), family="pair")


def run(s: Scene, out_dir=None, *, fields: bool = True, log=None) -> dict:
    """Half-space validity against the curvature a/R: every variant through both ladders
    (``Variant.scene``), so the curvature effect (FE extrapolated - MDR) stands with its
    error bar beside the tolerance, separated from the mesh error."""
    t0 = time.perf_counter()
    rows = []
    for v in s.typed_variants:
        sv = v.scene(s)
        mdr_ladder = [run_mdr(sv, n) for n in sv.mdr_cells]
        fe_ladder = [run_fe(sv, h)[0] for h in sv.fe_levels]
        ver = scene_verdicts(sv, fe_ladder, mdr_ladder)
        row = {"a_over_R": v.a_over_R, "nu": sv.nu1, "F0": sv.F0, "dofs": fe_ladder[-1]["dofs"],
               "holds": metrics.conjunction(ver), "grade": metrics.scene_grade(ver), "verdicts": ver,
               "runtime_s": sum(x["runtime_s"]["total"] for x in fe_ladder)}
        for q in ("contact_radius", "stick_radius", "dissipation"):
            x = ver[q]
            ref_q = abs(x["fem"]) if q == "dissipation" else mdr_ladder[-1]["contact_radius"]
            # FE extrapolated where its ladder is asymptotic, else its finest level (error bar: the spread)
            fe_q = x["fem_ladder"].get("extrapolated")
            fe_q = x["fem"] if fe_q is None else fe_q
            row[f"{q}_effect"] = None if fe_q is None or x["mdr"] is None else (fe_q - x["mdr"]) / ref_q
            row[f"{q}_effect_error"] = None if x["fem_error"] is None else (x["fem_error"] + x["mdr_error"]) / ref_q
        rows.append(row)
        d = ver["dissipation"]
        log(f"  a/R = {row['a_over_R']:.2%}, nu = {row['nu']:g}: dissipation MDR - FE "
            f"{d['difference'] / abs(d['fem']):+.3%} (error bars {(d['fem_error'] + d['mdr_error']) / abs(d['fem']):.3%}, "
            f"tolerance {d['tolerance'] / abs(d['fem']):.2%}): {row['grade']}")
    return result_of(s, KEY, rows, t0, out_dir, figure)


def table(res) -> list:
    lines = ["Curvature effect = FE extrapolated over its ladder minus MDR, in % of the MDR contact radius "
             "(radii) or of the FE dissipation, with the error bar of both sides; the verdict is that of the "
             "catalogue (error bars + tolerance) over all metrics of the variant.", "",
             "| a/R | nu | F0 (N) | FE DOFs | contact radius | stick radius | dissipation | MDR holds? |",
             "|---|---|---|---|---|---|---|---|"]

    def eff(r, q):
        e, err = r.get(f"{q}_effect"), r.get(f"{q}_effect_error")
        return "-" if e is None else f"{num(e, '+.2g', 100)} +- {num(err or 0, '.2g', 100)} %"

    for r in res["curvature"]:
        failed = [LABELS.get(q, q).split(" (")[0] for q, x in r["verdicts"].items() if x["holds"] is False]
        lines.append(f"| {num(r.get('a_over_R'), '.2g', 100)} % | {num(r.get('nu'), 'g')} | {num(r.get('F0'))} | {r.get('dofs')} | "
                     f"{eff(r, 'contact_radius')} | {eff(r, 'stick_radius')} | {eff(r, 'dissipation')} | "
                     f"{grade_text(r)}{': ' + ', '.join(failed) if failed else ''} |")
    return lines


def figure(result: dict, out_dir) -> dict:
    """Curvature effect (FE extrapolated - MDR, with its error bar) against a/R, one line per nu,
    for the dissipation and the radii, with the tolerances of the verdicts."""
    from ..figures import plt, save

    rows = result["curvature"]
    fig, axes = plt.subplots(1, 2, figsize=(10, 4.2))
    for ax, qs in zip(axes, (("dissipation",), ("contact_radius", "stick_radius"))):
        for q in qs:
            for nu, mk in ((0.1, "^"), (0.29, "o"), (0.45, "s")):
                sel = sorted([r for r in rows if abs(r["nu"] - nu) < 1e-9 and r.get(f"{q}_effect") is not None],
                             key=lambda r: r["a_over_R"])
                if not sel:
                    continue
                x = [100 * r["a_over_R"] for r in sel]
                y = [100 * r[f"{q}_effect"] for r in sel]
                e = [100 * (r[f"{q}_effect_error"] or 0.0) for r in sel]
                ax.errorbar(x, y, yerr=e, marker=mk, capsize=3, ls="-" if q != "stick_radius" else "--",
                            label=f"{q.replace('_', ' ')}, nu = {nu:g}")
            tol = rows[0]["verdicts"][q]["tolerance"]
            ref_q = abs(rows[0]["verdicts"][q]["fem"]) if q == "dissipation" else None
            if ref_q:
                ax.axhspan(-100 * tol / ref_q, 100 * tol / ref_q, color="0.9", zorder=0)
        ax.set_xscale("log")
        ax.set_xlabel("a / R (%)")
        ax.axhline(0.0, color="0.5", lw=0.8)
        ax.grid(alpha=0.3, which="both")
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
    axes[0].set_ylabel("FE - MDR, dissipation (% of the FE dissipation)")
    axes[1].set_ylabel("FE - MDR, radius (% of the contact radius)")
    axes[0].set_title("Dissipation (grey: tolerance)", fontsize=10)
    axes[1].set_title("Contact and stick radius", fontsize=10)
    fig.tight_layout()
    return {"curvature": save(fig, Path(out_dir) / "curvature.png")}
