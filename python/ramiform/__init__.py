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
        bezier_field,
        branching_tree,
        check,
        draw,
        grow,
        marching_cubes,
        mesh_skeleton,
        mpu_field,
        orient_normals,
        particles,
        patch_field,
        polygonize_tets,
        read_mesh,
        read_points,
        read_surface_points,
        read_skeleton,
        reconstruct,
        run_script,
        segment_field,
        skeleton_distances,
        skeleton_field,
        superquadric_field,
        tree_from_points,
        write_mesh,
        write_skeleton,
    )
    from ._ramiform import _mesh_command
except ImportError as _error:  # the module was not built: ramiform.forest still works
    _missing = _error

    def __getattr__(name):
        # Only the module's names: anything else (a submodule such as `forest`, imported by
        # `from ramiform import forest`) must stay an AttributeError, so that the import goes on.
        if name.startswith("_") or name not in __all__:
            raise AttributeError(f"module 'ramiform' has no attribute {name!r}")
        raise ImportError(
            f"ramiform.{name}: the compiled module ramiform._ramiform is not available "
            f"({_missing}); build ramiform with pybind11-dev and python3-dev installed "
            "(RAMIFORM_BUILD_PYTHON) and put <build>/python on PYTHONPATH"
        )
else:
    def mesh_file(input_path, output_path, **options):
        """``ramiform mesh INPUT -o OUTPUT [options]`` in this process, byte for byte the same file.

        Keywords are the command's options with ``_`` for ``-``: ``levels=2``, ``tolerance=0.02``,
        ``fit_radii=True``, ``cleanup=False`` (``--no-cleanup``), ``lod=[0.05, 0.15]``,
        ``threads=1``. The options are parsed by the CLI's own parser: an unknown one raises
        TypeError, a bad value ValueError (``mesh_file(): ...``), a bad input file ValueError with
        the file and line. The command's warnings become RuntimeWarnings. Returns the ``--stats``
        figures without the seconds.
        """
        from .forest import option_words  # noqa: PLC0415 (forest imports this module lazily)

        words = [str(input_path), "-o", str(output_path)] + option_words(options)
        stats = _mesh_command(words)
        stats.pop("seconds", None)
        return stats


__all__ = [
    "Field", "Mesh", "Skeleton", "bezier_field", "branching_tree", "check", "draw", "grow",
    "marching_cubes", "mesh_file", "mesh_skeleton", "mpu_field", "orient_normals", "particles",
    "patch_field", "polygonize_tets", "read_mesh", "read_points", "read_skeleton",
    "read_surface_points", "reconstruct", "run_script", "segment_field",
    "skeleton_distances", "skeleton_field", "superquadric_field", "tree_from_points", "write_mesh",
    "write_skeleton",
]
