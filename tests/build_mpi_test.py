#!/usr/bin/env python3
"""The build with a half-installed MPI (issue 30): Open MPI's runtime and wrapper but not its
headers (openmpi-bin without libopenmpi-dev). A fake `mpicxx` first on PATH stands in for that
wrapper: it cannot compile `#include <mpi.h>`.

  1. cmake configures (exit 0), says once why suite-mpi is not built, and makes no suite-mpi target;
  2. configured again in the same build folder without the fake (the packages now installed),
     it finds the real MPI and makes the suite-mpi target: the first configure's cache does not
     hide it.

usage: build_mpi_test.py CMAKE SOURCE_DIR       exit 0 when every claim holds
"""
import os
import shutil
import subprocess
import sys
import tempfile

cmake, source = sys.argv[1], sys.argv[2]
failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what)
    if not ok:
        failures.append(what)


def configure(build, path):
    env = dict(os.environ, PATH=path)
    return subprocess.run([cmake, "-S", source, "-B", build, "-DCMAKE_BUILD_TYPE=Release", "-DSUITE_BUILD_TESTS=OFF", "-DSUITE_LINK_TOP=OFF",
                           "-DSUITE_VALGRIND_TWIN=OFF", "-DSUITE_BUILD_GBENCH=OFF"], env=env, capture_output=True, text=True, timeout=300)


def has_target(build, name):
    with open(os.path.join(build, "Makefile")) as f:
        return ("\n" + name + ":") in f.read()


tmp = tempfile.mkdtemp(prefix="suite-build-mpi-")
try:
    fake = os.path.join(tmp, "bin")
    os.mkdir(fake)
    with open(os.path.join(fake, "mpicxx"), "w") as f:
        # Open MPI's opal_wrapper answers -showme from its data file, which openmpi-bin has:
        # the include and library folders named there come with libopenmpi-dev.
        f.write("#!/bin/sh\n# openmpi-bin's wrapper without libopenmpi-dev's headers\n"
                "case \"$1\" in\n"
                "  -showme:compile|--showme:compile) echo '-I/nonexistent/openmpi/include -pthread'; exit 0;;\n"
                "  -showme:link|--showme:link) echo '-pthread -L/nonexistent/openmpi/lib -lmpi_cxx -lmpi'; exit 0;;\n"
                "  -showme:incdirs|--showme:incdirs) echo '/nonexistent/openmpi/include'; exit 0;;\n"
                "  -showme:libdirs|--showme:libdirs) echo '/nonexistent/openmpi/lib'; exit 0;;\n"
                "  -showme:libs|--showme:libs) echo 'mpi_cxx mpi'; exit 0;;\n"
                "  -showme:version|--showme:version) echo 'mpicxx: Open MPI 4.1.4 (Language: C++)'; exit 0;;\n"
                "  -showme*|--showme*) echo 'g++ -I/nonexistent/openmpi/include -pthread -L/nonexistent/openmpi/lib -lmpi_cxx -lmpi'; exit 0;;\n"
                "esac\n"
                "for a; do last=$a; done\necho \"$last:1:10: fatal error: mpi.h: No such file or directory\" >&2\nexit 1\n")
    os.chmod(os.path.join(fake, "mpicxx"), 0o755)
    build = os.path.join(tmp, "build")
    r = configure(build, fake + os.pathsep + os.environ["PATH"])
    said = [l for l in r.stdout.splitlines() if "suite-mpi" in l]
    check(r.returncode == 0, "configure with a wrapper but no mpi.h succeeds (exit %d: %s)" % (r.returncode, r.stderr.strip()[-300:]))
    check(len(said) == 1 and "not built" in said[0] and "libopenmpi-dev" in said[0],
          "it says once why suite-mpi is not built, naming the package (%s)" % said)
    check(r.returncode == 0 and not has_target(build, "suite-mpi"), "no suite-mpi target")
    real = shutil.which("mpicxx")
    if not real:
        print("skip the second configure: no real MPI here (scripts/install-deps.sh test installs it)")
    else:
        r = configure(build, os.environ["PATH"])
        check(r.returncode == 0 and has_target(build, "suite-mpi"),
              "configured again with the real MPI, the same build folder finds it (exit %d; %s)" %
              (r.returncode, [l for l in r.stdout.splitlines() if "mpi" in l.lower()]))
finally:
    shutil.rmtree(tmp, ignore_errors=True)
print("build_mpi: %d claim(s) failed" % len(failures) if failures else "build_mpi: every claim holds")
sys.exit(1 if failures else 0)
