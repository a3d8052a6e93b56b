#pragma once
// What every finite element kernel sets up before its timed loop, in the point's arena and with
// its team: the mesh in the point's ordering, its CSR pattern, and (for the kernels after
// assembly) the matrices A and M. Every array is first touched by the thread that computes on
// it: coordinates and vertex arrays by vertex blocks, connectivity by element blocks, CSR rows
// by row blocks (blocks.hpp), so the harness's placement applies to each of them.
#include <cstdint>
#include <string>
#include <vector>

#include "harness/kernel/kernel.hpp"
#include "kernels/fem/assembly.hpp"
#include "kernels/fem/csr.hpp"

namespace suite::fem {

// The mesh of a point: --mesh, or the generated disk with at least `size` triangles.
std::string mesh_spec_of(const KernelConfig& cfg);

// A parameter of the point (the harness fills in the declared defaults).
double param(const KernelConfig& cfg, const std::string& name);

class FemPoint {
public:
    enum class Build { pattern, matrices };
    // Loads, orders and copies the mesh into the arena, builds the pattern and, for
    // Build::matrices, assembles A and M (serially: setup is not measured).
    void setup(Arena& arena, const KernelConfig& cfg, Build build);

    MeshArrays mesh;
    Pattern pattern;
    PatternScratch scratch;
    Matrices matrices;
    std::string spec;
    double delta = 0;
    int threads = 1;

    std::uint64_t nnz() const { return pattern.nnz(); }
    // "mesh SPEC (N triangles, V vertices, Z nonzeros), ORDERING": the start of every detail.
    std::string describe(const KernelConfig& cfg) const;
    // A vector of nv doubles in the arena, first touched by row blocks.
    double* vector(Arena& arena, const std::string& name) const;
};

// Bytes of the CSR structure, by the STREAM convention: values, column indices, row pointers.
inline double csr_bytes(std::uint64_t nnz, std::int64_t n) {
    return 12.0 * static_cast<double>(nnz) + 4.0 * static_cast<double>(n + 1);
}

// The checks of validate() common to the kernels: the mesh (fem_mesh.hpp), the memory it needs,
// and δ >= 0 (finite) when the kernel takes it.
void validate_fem(const KernelConfig& cfg, const std::string& kernel, bool takes_delta);

// The --delta parameter, and the mesh sizing every finite element kernel shares.
ParamInfo delta_param();
// The solver parameters of fem-cg, fem-eigen and their -dist twins: --cg-tol and --cg-max where
// the kernel runs CG, --tol where it runs the inverse iteration; and their checks (UsageError).
std::vector<ParamInfo> solver_params(bool cg, bool eigen);
void validate_solver_params(const KernelConfig& cfg, const std::string& kernel, bool cg, bool eigen);
void set_mesh_sizing(KernelEntry& e);

}  // namespace suite::fem
