"""# MDR on rough surfaces: the smooth profile or the equivalent one?

A literate example (run by the slow suite): the paper's steel sphere (R = 6 mm, F_N = 0.5 N,
mu = 0.2, F_x = mu F_N / 2 under force control) on self-affine rough surfaces, through three
models side by side (``rough.equivalent.mdr_against_rough``):

- the rough half-space: FFT boundary elements (tamaas) for the pressure, then Coulomb friction cell by
  cell with memory for the fretting cycles (``rough.tangential``);
- MDR with the *equivalent profile* of the rough contact's own normal force-approach curve
  (``mdr.equivalent.EquivalentProfile``: a(d) = F'(d) / (2 E*), g the inverse of a);
- MDR with the smooth sphere, the paper's model.

Run it::

    python docs/examples/rough_equivalent.py            # prints the table
    python docs/examples/rough_equivalent.py --write    # rewrites its block in docs/rough.md
    python docs/examples/rough_equivalent.py --check    # compares with that block (exit 1 on a difference)
"""
import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from mdr import reference as ref  # noqa: E402
from mdr.materials import Materials  # noqa: E402
from mdr.paper import R_INDENTER, TABLE2  # noqa: E402
from mdr.profiles import Sphere  # noqa: E402
from rough.equivalent import mdr_against_rough  # noqa: E402
from rough.normal import Grid  # noqa: E402
from rough.surfaces import RoughnessParams, generate  # noqa: E402

# ## The set-up
# The grid: a period of 16 Hertz radii (the periodic images cost ~0.1 %), pixels of a/8. The
# surfaces: rms 30 and 100 nm (against Hertz's approach of 125 nm: from a perturbation to a contact
# that breaks up), Hurst 0.8, wavelengths from a/2 to 4 a, three realisations each. The paper's own
# roughness (rms 1-3 um) is far beyond: its contact spreads over several Hertz radii and needs grids
# of 512^2 and more, left for the roughness family of the catalogue.
MAT = Materials()
F0, MU = TABLE2["F0"], TABLE2["mu1"]
A = float(ref.hertz(F0, R_INDENTER, MAT.E_star)["a"])
GRID = Grid(16 * A, 128)
RMS = (30e-9, 100e-9)
SEEDS = (0, 1, 2)
PAGE = ROOT / "docs" / "rough.md"
BEGIN = "<!-- generated: rough-equivalent (python docs/examples/rough_equivalent.py) -->"
END = "<!-- end generated -->"


def surface(rms, seed):
    P = GRID.period
    return generate(RoughnessParams(rms=rms, hurst=0.8, lambda_short=P / 32, lambda_long=P / 4, size=P, n=GRID.n,
                                    seed=seed))


def pct(values) -> str:
    """mean +- standard error of the mean, in %."""
    v = 100 * np.asarray(values)
    if v.size == 1:
        return f"{v[0]:+.2f} %"
    return f"{v.mean():+.1f} +- {v.std(ddof=1) / np.sqrt(v.size):.1f} %"


# ## The runs
# Each row: the models' dissipation and stiffness relative to the rough half-space's, as mean +- SEM
# over the realisations. Without roughness all three agree within the grid's error (0.1 %).
def table() -> list:
    lines = ["| surface | contact area / Hertz | MDR equivalent: dissipation | stiffness | "
             "MDR smooth: dissipation | stiffness |", "|---|---|---|---|---|---|"]
    cases = [("smooth", None, [None])] + [(f"rms {rms * 1e9:.0f} nm, {len(SEEDS)} seeds", rms, SEEDS) for rms in RMS]
    for label, rms, seeds in cases:
        rows = [mdr_against_rough(Sphere(R_INDENTER), MAT, MU, F0, 0.5 * MU * F0, GRID,
                                  None if rms is None else surface(rms, s)) for s in seeds]
        rel = {(m, k): [r["relative"][m][k] for r in rows] for m in ("mdr_equivalent", "mdr_smooth")
               for k in ("dissipation", "stiffness")}
        area = np.mean([r["rough_halfspace"]["contact_area"] for r in rows]) / (np.pi * A ** 2)
        lines.append(f"| {label} | {area:.2f} | {pct(rel['mdr_equivalent', 'dissipation'])} | "
                     f"{pct(rel['mdr_equivalent', 'stiffness'])} | {pct(rel['mdr_smooth', 'dissipation'])} | "
                     f"{pct(rel['mdr_smooth', 'stiffness'])} |")
    return lines


# ## Into the docs
# The table lives in docs/rough.md between two marker lines; ``--check`` compares the numbers within
# 10 % of the larger plus 0.5 (another CPU's rounding moves the last digit of a mean, not its size).
def block(text: str) -> tuple:
    lines = text.split("\n")
    i = lines.index(BEGIN)
    return lines, i + 1, lines.index(END, i + 1)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="MDR with the smooth or the equivalent profile against the rough "
                                             "half-space (prints the table of docs/rough.md)")
    mode = ap.add_mutually_exclusive_group()
    mode.add_argument("--write", action="store_true", help="rewrite the table's block in docs/rough.md")
    mode.add_argument("--check", action="store_true", help="compare with that block; exit 1 on a difference")
    args = ap.parse_args(argv)
    new = table()
    print("\n".join(new))
    if not (args.write or args.check):
        return 0
    lines, i, j = block(PAGE.read_text())
    if args.write:
        PAGE.write_text("\n".join(lines[:i] + new + lines[j:]))
        return 0
    import re

    num = re.compile(r"[-+]?\d+\.\d+")
    bad = [f"docs: {a}\nrun:  {b}" for a, b in zip(lines[i:j], new)
           if num.sub("#", a) != num.sub("#", b)
           or any(abs(float(x) - float(y)) > 0.1 * max(abs(float(x)), abs(float(y))) + 0.5
                  for x, y in zip(num.findall(a), num.findall(b)))]
    if len(lines[i:j]) != len(new):
        bad.append(f"{j - i} lines in the docs against {len(new)}")
    print("\n".join(bad) or "docs/rough.md: current", file=sys.stderr)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
