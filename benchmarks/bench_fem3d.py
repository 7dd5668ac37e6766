"""Cost of the 3D half-model (issue 13): DOFs, mesh, assembly, factorisation and solve times.

Block: half cylinder of radius and height 25 a_ref, contact half disk 1.25 a_ref,
uniform pressure on it (the Boussinesq case of tests/test_fem3d.py). Run:

    PYTHONPATH=. python benchmarks/bench_fem3d.py [h_contact ...]
"""
import sys
import time

import numpy as np

from fem.solid3d.elastic import dirichlet_dofs, pressure_load, stiffness3d
from fem.solvers import blas_threads, factorize
from meshes.half3d import Half3DMeshParams, build_mesh3d

E, NU, P = 200e9, 0.3, 1e8


def run(h):
    t0 = time.perf_counter()
    m = build_mesh3d(Half3DMeshParams(a_ref=1.0, h_contact=h, size=25.0, height=25.0)).mesh
    t1 = time.perf_counter()
    K, b = stiffness3d(m, E, NU)
    f = pressure_load(m, b, P)
    t2 = time.perf_counter()
    fix = dirichlet_dofs(b, m)
    free = np.setdiff1d(np.arange(K.shape[0]), fix)
    Kff = K[free][:, free].tocsc()
    with blas_threads(1):
        t3 = time.perf_counter()
        fac = factorize(Kff)
        t4 = time.perf_counter()
        fac.solve(f[free])
        t5 = time.perf_counter()
    contact_nodes = np.unique(m.facets[:, m.boundaries["contact"]]).size + \
        np.unique(m.f2e[:, m.boundaries["contact"]]).size
    return dict(h=h, tets=m.t.shape[1], dofs=K.shape[0], contact_nodes=contact_nodes, mesh_s=t1 - t0,
                assembly_s=t2 - t1, factor_s=t4 - t3, solve_s=t5 - t4, backend=fac.backend)


def main(levels):
    print("| h_contact / a | tets | DOFs | contact P2 nodes | mesh (s) | assembly (s) | factorisation (s) "
          "| one solve (s) | backend |")
    print("|---|---|---|---|---|---|---|---|---|")
    for h in levels:
        r = run(h)
        print(f"| {r['h']:g} | {r['tets']} | {r['dofs']} | {r['contact_nodes']} | {r['mesh_s']:.2f} | "
              f"{r['assembly_s']:.2f} | {r['factor_s']:.2f} | {r['solve_s']:.3f} | {r['backend']} |", flush=True)


if __name__ == "__main__":
    main([float(x) for x in sys.argv[1:]] or [0.2, 0.1, 0.07, 0.05])
