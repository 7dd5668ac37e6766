"""The family ``validity``: the half-space assumption against finite bodies, the FE block and/or cap
shrunk towards the contact (multiples of a_ref) at one mesh level, against the default bodies and MDR.
"""
from __future__ import annotations

import math
import time
from dataclasses import dataclass
from pathlib import Path

from common.errors import InputError

from .. import metrics
from . import result_of
from ..scenes import Scene, a_ref
from ..sides import closed_forms, run_fe, run_mdr
from ..text import num, pct

#: the key of the family's rows in a result, and the title of its figure in the report
KEY = 'validity'
TITLE = 'validity'


#: the bodies' size of the default FE model, in contact radii (meshes.axisym: block 200 a_ref, the cap as high)
VALIDITY_DEFAULT_SIZE = 200.0
#: the smallest body a variant may shrink to, in contact radii (the probe of the half-space comparable
#: displacement sits inside a body of 2.5 a)
VALIDITY_MIN_SIZE = 2.5


@dataclass(frozen=True)
class Variant:
    """One variant of a validity scene: the FE block's and/or the cap's size in contact radii (a_ref; None:
    the default body, ``VALIDITY_DEFAULT_SIZE``). ``Variant()`` is the default bodies, the row every
    variant is compared with."""

    block: float | None = None
    cap: float | None = None

    @classmethod
    def of(cls, v: dict, scene: Scene) -> "Variant":
        """The mapping ``v`` checked: the keys ``block`` and/or ``cap``, each a number > 2.5."""
        ok = bool(v) and set(v) <= {"block", "cap"} and all(
            isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) and x > VALIDITY_MIN_SIZE
            for x in v.values())
        if not ok:
            raise InputError(f"scene {scene.name}: a validity variant holds block and/or cap, sizes in contact "
                             f"radii > {VALIDITY_MIN_SIZE:g}, got {v!r}")
        return cls(**{k: float(x) for k, x in v.items()})

    @property
    def is_default(self) -> bool:
        return self.block is None and self.cap is None

    @property
    def sizes(self) -> tuple:
        """(block, cap) in contact radii, the default body where the variant leaves one out."""
        return (VALIDITY_DEFAULT_SIZE if self.block is None else self.block,
                VALIDITY_DEFAULT_SIZE if self.cap is None else self.cap)

    @property
    def label(self) -> str:
        """Which body is shrunk: 'block 3 a (cap 200 a)', 'cap 3 a (block 200 a)', 'block 3 a, cap 3 a'."""
        if self.is_default:
            return f"default ({VALIDITY_DEFAULT_SIZE:g} a)"
        if self.block is not None and self.cap is not None:
            return f"block {self.block:g} a, cap {self.cap:g} a"
        kind, x, other = ("block", self.block, "cap") if self.cap is None else ("cap", self.cap, "block")
        return f"{kind} {x:g} a ({other} {VALIDITY_DEFAULT_SIZE:g} a)"

    def mesh_options(self, a: float) -> dict:
        """The FE model's options (``validation.sides.run_fe``) for contact radius ``a`` (m): each body at
        its own size (the default cap is as high as the block, so a block-only variant keeps the cap at
        the default size explicitly); {} for the default. The displacement's probe is the mesh's default,
        midway between the contact zone and 0.8 of the shallower body (the sphere's cap at most its
        equator: a large contact's cap is the sphere's, not 200 a)."""
        if self.is_default:
            return {}
        block, cap = self.sizes
        return {"block_size": block * a, "indenter_height": cap * a}


def run(s: Scene, out_dir=None, *, fields: bool = True, log=None) -> dict:
    """Half-space validity: FE with the block or the cap shrunk (multiples of a_ref), one mesh level."""
    t0 = time.perf_counter()
    h = s.fe_levels[-1]
    a = a_ref(s)
    mdr = run_mdr(s, s.mdr_cells[-1])
    closed = closed_forms(s)
    base, _ = run_fe(s, h)
    rows = []
    for v in (Variant(),) + s.typed_variants:
        res = base if v.is_default else run_fe(s, h, **v.mesh_options(a))[0]
        block, cap = v.sizes
        row = {"variant": v.label, "block_over_a": block, "cap_over_a": cap, "dofs": res["dofs"]}
        for q in ("contact_radius", "stick_radius", "dissipation"):
            row[q] = res[q]
            row[f"{q}_mdr_minus_fe"] = metrics.rel(mdr[q], res[q])
            row[f"{q}_vs_default"] = metrics.rel(res[q], base[q])
        row["bulk_compliance"] = res["bulk_compliance"]
        row["runtime_s"] = res["runtime_s"]["total"]
        rows.append(row)
        log(f"  {row['variant']}: a {row['contact_radius']:.4g} m (MDR-FE {row['contact_radius_mdr_minus_fe']:+.2%})")
    return result_of(s, KEY, rows, t0, out_dir, figure, closed_form=closed, mdr=mdr, fem=base)


def table(res) -> list:
    lines = ["Size effect = FE of the small body against the default 200 a bodies at the same mesh (the mesh "
             "error cancels; the default is a half-space within it): the error a half-space model makes.", "",
             "| variant | DOFs | a: size effect | c: size effect | dW: size effect | a: MDR - FE | c: MDR - FE "
             "| dW: MDR - FE | bulk compliance (m/N) |",
             "|---|---|---|---|---|---|---|---|---|"]
    for r in res["validity"]:
        lines.append(f"| {r['variant']} | {r['dofs']} | {pct(r['contact_radius_vs_default'], 3)} | "
                     f"{pct(r['stick_radius_vs_default'], 3)} | {pct(r['dissipation_vs_default'], 3)} | "
                     f"{pct(r['contact_radius_mdr_minus_fe'])} | {pct(r['stick_radius_mdr_minus_fe'])} | "
                     f"{pct(r['dissipation_mdr_minus_fe'])} | {num(r.get('bulk_compliance'))} |")
    return lines


def figure(result: dict, out_dir) -> dict:
    """Size effect: change of the FE answer (contact radius, stick radius, dissipation) when the
    block or the cap shrinks, against size / a, relative to the default 200 a bodies at the same
    mesh (which removes the mesh error common to all variants; the default is a half-space
    within that error, so this is the error a half-space model makes for the small body)."""
    from ..figures import plt, save

    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    rows = result["validity"]
    big = max(max(r["block_over_a"], r["cap_over_a"]) for r in rows)  # the default bodies' size
    kinds = {"block": lambda r: r["block_over_a"] < big <= r["cap_over_a"],
             "cap": lambda r: r["cap_over_a"] < big <= r["block_over_a"],
             "both": lambda r: max(r["block_over_a"], r["cap_over_a"]) < big}
    for (kind, pick), mk, ls in zip(kinds.items(), ("o", "s", "^"), ("-", "--", ":")):
        sel = sorted([r for r in rows if pick(r)], key=lambda r: min(r["block_over_a"], r["cap_over_a"]))
        if not sel:
            continue
        x = [min(r["block_over_a"], r["cap_over_a"]) for r in sel]
        for q, c in (("contact_radius", "tab:blue"), ("stick_radius", "tab:green"), ("dissipation", "tab:red")):
            y = [max(abs(r[f"{q}_vs_default"] or 0.0), 1e-7) * 100 for r in sel]
            ax.semilogy(x, y, marker=mk, color=c, ls=ls,
                        label=f"{q.replace('_', ' ')}, {'block and cap' if kind == 'both' else kind + ' alone'} shrunk")
    ax.set_xscale("log")
    ax.set_xlabel("block or cap size / contact radius")
    ax.set_ylabel("|FE(size) - FE(200 a)| (%)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    ax.set_title("Where the half-space assumption breaks", fontsize=10)
    fig.tight_layout()
    return {"validity": save(fig, Path(out_dir) / "validity.png")}
