"""# Your own apparatus point: MDR and the FE contact law in the same apparatus

A literate example (the fast suite runs it, ``tests/test_examples.py``): one operating point of the
paper's fretting apparatus (Willert, Machines 11 (2023) 484: the brass plates, the Si3N4 bedding, the
piezo stroke u_A) with a contact of your own, once with the MDR law (the half-space, milliseconds) and
once with the axisymmetric FE law of the same finite bodies (seconds), and the slip index of each: the
dissipation per cycle over 4 mu1 F0 u_A, what the paper's Figs. 8-9 plot.

Change the numbers below to your rig's: the indenter (R, and b for a truncated sphere), the axis
stiffness k_x, the loads and the stroke. Run it::

    python docs/examples/apparatus_point.py
"""
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from fem.apparatus import fem_apparatus_result  # noqa: E402
from fem.options import FEOptions  # noqa: E402
from mdr.apparatus import Apparatus, mdr_apparatus_result  # noqa: E402
from mdr.loading import Loading  # noqa: E402
from mdr.materials import Materials  # noqa: E402
from mdr.profiles import TruncatedSphere  # noqa: E402

# ## The point
# A truncated sphere (R = 6 mm, a flat face of b = 20 um) in the apparatus with an axis of 2 N/um, the
# paper's Table 2 load: F_N(t) = 0.5 + 0.1 sin(2 pi t) N, the piezo stroke u_A = 150 nm, mu1 = 0.2 at the
# contact and mu2 = 0.1 at the bedding. Four cycles of 200 steps (the first from rest).
PROFILE = TruncatedSphere(6e-3, 20e-6)
MAT = Materials()
MU1 = 0.2
APP = Apparatus(kx=2e6, mu2=0.1)
LOADING = Loading.apparatus(0.5, dF=0.1, ua=150e-9, cycles=4, steps=200)


# ## Both laws in the apparatus
# ``mdr_apparatus_result`` drives the MDR law of 400 springs; ``fem_apparatus_result`` the axisymmetric FE
# law (Fourier modes 0 and 1 on an r-z mesh of the indenter's cap and the block) with the contact's own
# displacement, so the apparatus's compliances are counted once. ``h_contact`` is the FE element size on
# the contact over its radius: 0.1 here (seconds); the catalogue's ladders go to 0.0125.
def main(h_contact=0.1, out=print) -> dict:
    """The slip index and the dissipation per cycle of both laws at the point."""
    mdr = mdr_apparatus_result(PROFILE, MAT, APP, MU1, LOADING)
    fem = fem_apparatus_result(PROFILE, MAT, APP, MU1, LOADING, FEOptions(h_contact=h_contact))
    rows = {"MDR (half-space)": mdr, f"FE (finite bodies, h = {h_contact:g} a)": fem}
    out("| law | slip index | dissipation per cycle (J) | contact radius at F0 (um) |")
    out("|---|---|---|---|")
    for name, r in rows.items():
        out(f"| {name} | {r['slip_index']:.4f} | {r['dissipation']:.4g} | {r['contact_radius'] * 1e6:.3f} |")
    return {"mdr": mdr, "fem": fem}


# ## What it shows
# At the paper's scale the bodies are large against the contact (a/R under 1 %), so the FE law of the
# real bodies and MDR's half-space give the same slip index within the FE mesh's error: the catalogue's
# scenes app-kx1 .. app-kx20 and docs/comparison.md measure that difference with both models' error bars.
if __name__ == "__main__":
    main()
