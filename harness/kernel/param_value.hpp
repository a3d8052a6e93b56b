#pragma once
// A kernel parameter's value (kernel.hpp, ParamInfo): a number, or for a named parameter the name
// chosen, so that a record keeps the name and never a position in a list.
#include <map>
#include <string>
#include <variant>

namespace suite {

using ParamValue = std::variant<double, std::string>;
using Params = std::map<std::string, ParamValue>;
// "0.05" for a number, the name itself for a named parameter: how labels and CSV show a value.
std::string param_text(const ParamValue& v);

}  // namespace suite
