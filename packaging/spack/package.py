# Spack recipe for the suite: `spack install suite` once this directory is in a Spack repository
# (docs/install.md), or `spack dev-build suite@main` from a clone of the source tree.
from spack.package import *


class Suite(CMakePackage):
    """NUMA/cache micro-benchmark suite with instrumentation: STREAM and indirect kernels,
    pointer-chase latency, finite element and Material Point Method kernels in natural, random
    and space-filling-curve orders, with hwloc pinning, libnuma placement, perf counters
    (libpfm4), RAPL energy, verified results and a CI regression gate."""

    # Where the suite is published; point it at your clone (or use spack dev-build).
    git = "file:///srv/git/suite"

    # As the LICENSE file at the top of the tree says (tests/install_test.py holds them equal).
    license("BSD-3-Clause")

    version("main", branch="main")

    variant("mpi", default=True, description="build suite-mpi: the kernels on every rank of an MPI job")
    variant("metis", default=True, description="METIS: suite matrix's nested dissection and fem-*-dist's METIS partition")
    variant("suitesparse", default=True, description="SuiteSparse: suite matrix's AMD ordering and CHOLMOD factorisation")
    # suite matrix needs both libraries; the build has one switch for them (SUITE_WITH_SPARSE).
    conflicts("+metis~suitesparse", msg="suite matrix needs SuiteSparse and METIS together")
    conflicts("~metis+suitesparse", msg="suite matrix needs SuiteSparse and METIS together")

    depends_on("cmake@3.20:", type="build")
    depends_on("pkgconfig", type="build")
    depends_on("hwloc@2:")
    depends_on("numactl")
    depends_on("libpfm4")
    depends_on("nlohmann-json@3.9:")
    depends_on("cli11@2:")
    depends_on("sqlite@3:")
    depends_on("boost+graph@1.71:")
    depends_on("mpi", when="+mpi")
    depends_on("metis@5:", when="+metis")
    depends_on("suite-sparse", when="+suitesparse")
    # The figures (plots/*.py, installed in share/suite/plots).
    depends_on("python@3.8:", type="run")
    depends_on("py-matplotlib", type="run")
    depends_on("py-numpy", type="run")

    def cmake_args(self):
        spec = self.spec
        return [
            self.define_from_variant("SUITE_WITH_MPI", "mpi"),
            self.define("SUITE_WITH_SPARSE", spec.satisfies("+metis+suitesparse")),
            # Spack's compiler wrappers carry the target's -march: none of the suite's own.
            self.define("SUITE_ARCH", ""),
            self.define("SUITE_BUILD_TESTS", False),
            self.define("SUITE_BUILD_GBENCH", False),
            self.define("SUITE_LINK_TOP", False),
            self.define("SUITE_VALGRIND_TWIN", False),
        ]
