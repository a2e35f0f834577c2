#pragma once
// Private to src/io: the items of an array of tables in a flat scenario.
#include <string>
#include <vector>

#include "viaduct/io/scenario.hpp"

namespace viaduct::io::detail {

/// The indices i of the items head[i] present in `f` ("sweep.variants" -> 0, 1, 2), ascending.
std::vector<std::size_t> item_indices(const FlatScenario& f, const std::string& head);

}  // namespace viaduct::io::detail
