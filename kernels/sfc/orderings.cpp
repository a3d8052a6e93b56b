#include "kernels/sfc/orderings.hpp"

#include <stdexcept>

namespace suite::sfc {

const ChoiceTable<Ordering>& mesh_orderings() {
    using How = Ordering::How;
    static const ChoiceTable<Ordering> table{
        "ordering",
        {{"natural", "as the file or the generator numbers them", {How::as_given}},
         {"random", "elements and vertices shuffled apart by --seed", {How::shuffled}},
         {"morton", "elements along the Morton (Z) curve, vertices by first touch", {How::sorted, Method::morton}},
         {"hilbert", "elements along the Hilbert curve, vertices by first touch", {How::sorted, Method::hilbert}},
         {"morton-recursive",
          "morton's order, its keys by the thesis's recursive halving (to time against morton's)",
          {How::sorted, Method::morton_recursive, false}},
         {"rcm", "vertices by Reverse Cuthill-McKee, elements following them", {How::sorted, Method::rcm}}}};
    return table;
}

const ChoiceTable<Ordering>& sorting_orderings() {
    static const ChoiceTable<Ordering> table =
        mesh_orderings().subset([](const Ordering& o) { return o.how == Ordering::How::sorted; });
    return table;
}

const ChoiceTable<Ordering>& distinct_orderings() {
    static const ChoiceTable<Ordering> table = mesh_orderings().subset([](const Ordering& o) { return o.own_order; });
    return table;
}

const std::string& as_given_name() {
    for (const auto& c : mesh_orderings().all())
        if (c.what.how == Ordering::How::as_given) return c.name;
    throw std::logic_error("the mesh orderings have none that leaves the mesh as given");
}

const std::string& method_name(Method m) {
    for (const auto& c : sorting_orderings().all())
        if (c.what.method == m) return c.name;
    throw std::logic_error("a sorting method without an ordering's name");
}

Method parse_method(const std::string& name) { return sorting_orderings().at(name).what.method; }

}  // namespace suite::sfc
