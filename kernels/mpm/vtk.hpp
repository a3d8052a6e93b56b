#pragma once
// Particle snapshots for ParaView and meshio: the text of a VTK XML UnstructuredGrid (.vtu) of
// the particles, and of the .pvd collection that lists a run's snapshots with their times. The
// functions only render; the caller writes the text (suite mpm through OutputDir::write).
//
// Why here and not in harness/results/: the writers there render result records and may not
// see kernels/ (tests/layout_test.py), while this one needs Particles; it sits beside the
// mesh's own .vtu writer (kernels/mesh/writers.hpp), one folder a kind of data.
//
// Every array is written in VTK's inline binary form: base64 of a UInt64 byte count followed
// by the little- (or big-, as the machine is) endian values, so every double reads back
// exactly (ASCII would need 17 digits a value and twice the bytes).
#include <string>
#include <vector>

#include "kernels/mpm/mpm.hpp"

namespace suite::mpm {

// One VTK_VERTEX cell a particle, in the particles' storage order. Point data: id (UInt32),
// velocity (3 components), stress (6 components named xx, yy, zz, xy, yz, zx), volume, mass.
std::string particles_vtu(const Particles& p);

// A snapshot of a collection: the .vtu's file name (relative to the .pvd) and its time.
struct SnapshotEntry {
    std::string file;
    double time = 0;
};
std::string collection_pvd(const std::vector<SnapshotEntry>& snapshots);

// Standard base64 (RFC 4648, with '=' padding) of `n` bytes; exposed for the tests.
std::string base64(const void* data, std::size_t n);

}  // namespace suite::mpm
