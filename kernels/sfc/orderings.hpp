#pragma once
// The mesh orderings, one table (harness/common/choice_table.hpp): how a mesh's elements and
// vertices are numbered before a kernel walks them. Every user reads its orderings here, never
// from a copy: the finite element kernels, sfc-build, `suite traverse`, `suite matrix` (which
// adds orderings of the matrix itself, kernels/fem/ordering_study.hpp) and `suite run --help`.
// Records keep the name.
#include <string>

#include "harness/common/choice_table.hpp"

namespace suite::sfc {

// The orderings that sort elements by a key: the three curves and RCM.
enum class Method { morton, hilbert, morton_recursive, rcm };

struct Ordering {
    enum class How { as_given, shuffled, sorted };
    How how = How::as_given;
    Method method = Method::morton;  // how == sorted: what the elements are sorted by
    // false for another way of computing an order an earlier entry gives (morton-recursive:
    // morton's keys by recursive halving). Kernels that measure the ordered data, not the making
    // of the order, would only repeat the earlier entry's numbers with it.
    bool own_order = true;
};

// Every mesh ordering (`suite traverse` takes them all).
const ChoiceTable<Ordering>& mesh_orderings();
// Those that sort by a key: what sfc-build times.
const ChoiceTable<Ordering>& sorting_orderings();
// Each order once: what the kernels that walk ordered data take (fem).
const ChoiceTable<Ordering>& distinct_orderings();

// The name of the mesh as given ("natural"): a default where no ordering is asked for.
const std::string& as_given_name();
// The name of a sorting ordering's method, for messages.
const std::string& method_name(Method m);

// A sorting ordering's method; throws UsageError naming sorting_orderings() otherwise.
Method parse_method(const std::string& name);

}  // namespace suite::sfc
