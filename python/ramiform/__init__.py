# SPDX-License-Identifier: MIT
# Copyright (c) 2026 the ramiform authors
"""ramiform: skeleton-based implicit surfaces, watertight meshes of trees and neurons.

The functions and classes come from the compiled module ``ramiform._ramiform`` (docs/python.md);
``ramiform.forest`` meshes many trees with Dask and needs only the ``ramiform`` command.
"""

try:
    from ._ramiform import (  # noqa: F401
        Field,
        Mesh,
        Skeleton,
        branching_tree,
        check,
        grow,
        marching_cubes,
        mesh_skeleton,
        polygonize_tets,
        read_mesh,
        read_points,
        read_skeleton,
        run_script,
        skeleton_field,
        write_mesh,
        write_skeleton,
    )
except ImportError as _error:  # the module was not built: ramiform.forest still works
    _missing = _error

    def __getattr__(name):
        raise ImportError(
            f"ramiform.{name}: the compiled module ramiform._ramiform is not available "
            f"({_missing}); build ramiform with pybind11-dev and python3-dev installed "
            "(RAMIFORM_BUILD_PYTHON) and put <build>/python on PYTHONPATH"
        )

__all__ = [
    "Field", "Mesh", "Skeleton", "branching_tree", "check", "grow", "marching_cubes", "mesh_skeleton",
    "polygonize_tets", "read_mesh", "read_points", "read_skeleton", "run_script",
    "skeleton_field", "write_mesh", "write_skeleton",
]
