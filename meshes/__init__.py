"""Cached gmsh meshes of the axisymmetric indenter-on-block section (see meshes.axisym)."""
from .axisym import AxisymMesh, AxisymMeshParams, build_mesh, export_vtu, from_meshio, generate_meshio
from .cache import cached_mesh, default_cache_dir, load_mesh, mesh_key, save_mesh

__all__ = ["AxisymMesh", "AxisymMeshParams", "build_mesh", "cached_mesh", "default_cache_dir",
           "export_vtu", "from_meshio", "generate_meshio", "load_mesh", "mesh_key", "save_mesh"]
