#pragma once
// The checks of sfc-build's answer, one per phase, each a property of the output that a
// wrong or missing result breaks:
//   keys      every key decodes back to the cell of its element's centroid (an inverse written
//             apart from the encoders), and a sample agrees with another encoder (morton with
//             morton-recursive and back; hilbert with the portable interleave); RCM: the vertex
//             numbering is a permutation and each key is the smallest number among the corners;
//   sort      perm is a permutation, keys are non-decreasing along it, equal keys in element order;
//   renumber  the vertex numbering is a permutation, element i has the corners of element
//             perm[i] at the same coordinates, and (curves) vertices are numbered in order of
//             first touch along the new element order.
#include <string>

#include "kernels/sfc/pipeline.hpp"

namespace suite::sfc {

struct CheckResult {
    bool passed = true;
    std::string what;     // what was checked
    std::string failure;  // the first thing found wrong
};

class Checks {
public:
    Checks(const mesh::MeshView& in, Method method, int depth, const PipelineArrays& arrays, const KeyFrame& frame)
        : in_(in), method_(method), depth_(depth), a_(arrays), frame_(frame) {}
    CheckResult keys() const;
    CheckResult sort() const;
    CheckResult renumber() const;

private:
    mesh::MeshView in_;
    Method method_;
    int depth_;
    PipelineArrays a_;
    KeyFrame frame_;
};

}  // namespace suite::sfc
