// libFuzzer target of the thesis-format reader: any input must give either a mesh that keeps
// the readers' promises or a MeshError; never a crash, an out-of-bounds access (ASan), undefined
// behaviour (UBSan), a hang or an unbounded allocation.
// SOURCES: kernels/mesh/mesh.cpp kernels/mesh/read_text.cpp kernels/mesh/read_msh.cpp kernels/mesh/read_mesh.cpp harness/common/input_file.cpp harness/common/sysfs_file.cpp
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "kernels/mesh/mesh_error.hpp"
#include "kernels/mesh/readers.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    try {
        const suite::mesh::Mesh m =
            suite::mesh::read_text_mesh(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.txt");
        if (m.elements() == 0 || m.dim != 2) std::abort();
        for (auto v : m.conn)
            if (v >= m.vertices()) std::abort();
    } catch (const suite::mesh::MeshError&) {
    }
    return 0;
}
