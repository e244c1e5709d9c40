# SPDX-License-Identifier: MIT
"""The pip build's one custom step: build the C++ core with CMake (metadata: pyproject.toml).

`python -m pip install .` runs this through setuptools. The extension ``slidebeam._core`` is
built by CMakeLists.txt (target _core, which also writes effect_specs.json) in a build tree of
its own (build/python/, not the build/ of scripts/setup.sh, whose module goes to python/slidebeam/)
and installed into the wheel with ``cmake --install --component python``.

Environment: SLIDEBEAM_BUILD_JOBS (parallel compile jobs, default: all cores), CMAKE_ARGS (extra
-D options for the configure step).
"""
from __future__ import annotations

import os
import shlex
import subprocess
import sys
from pathlib import Path

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

ROOT = Path(__file__).resolve().parent


class CMakeExtension(Extension):
    def __init__(self, name: str) -> None:
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext: Extension) -> None:
        # <build_lib>/slidebeam/_core.<suffix>.so: CMake installs into <build_lib> (or, for an
        # editable install, the source package folder)
        target = Path(self.get_ext_fullpath(ext.name)).resolve()
        package_dir = target.parent
        prefix = package_dir.parent
        tree = Path(self.build_temp).resolve() / "cmake"
        products = tree / "package"  # where the build writes _core and effect_specs.json
        products.mkdir(parents=True, exist_ok=True)
        # pip's isolated build hides the system site-packages through PYTHONPATH; CMake asks the
        # interpreter for petsc4py's, mpi4py's and numpy's headers, which are Debian's.
        env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "PYTHONNOUSERSITE")}
        configure = ["cmake", "-S", str(ROOT), "-B", str(tree),
                     "-DCMAKE_BUILD_TYPE=Release",
                     f"-DPython3_EXECUTABLE={sys.executable}",
                     f"-DSLIDEBEAM_PACKAGE_DIR={products}",
                     "-DSLIDEBEAM_PYTHON_INSTALL_DIR=slidebeam",
                     "-DSLIDEBEAM_BUILD_TESTS=OFF",
                     *shlex.split(os.environ.get("CMAKE_ARGS", ""))]
        jobs = os.environ.get("SLIDEBEAM_BUILD_JOBS") or str(os.cpu_count() or 1)
        self._run(configure, env)
        self._run(["cmake", "--build", str(tree), "--target", "_core", "-j", jobs], env)
        self._run(["cmake", "--install", str(tree), "--component", "python", "--prefix", str(prefix)], env)
        if not target.is_file():
            raise RuntimeError(f"CMake did not install {target.name} into {package_dir}")

    def _run(self, cmd: list[str], env: dict[str, str]) -> None:
        print("setup.py:", " ".join(cmd), flush=True)
        subprocess.run(cmd, check=True, env=env)


setup(ext_modules=[CMakeExtension("slidebeam._core")],
      cmdclass={"build_ext": CMakeBuild},
      options={"build": {"build_base": "build/python"}})
